use pfcam::compose;
use pfcam::geometry::{BoolOp, Composition, Part, PartSource, Vec2};
fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> { vec![Vec2::new(x0,y0),Vec2::new(x1,y0),Vec2::new(x1,y1),Vec2::new(x0,y1)] }
fn main() {
    let parts = vec![
        Part{name:"a".into(), source: PartSource::Polygon(rect(0.,0.,100.,60.)), level:None, singularities:None},
        Part{name:"b".into(), source: PartSource::Polygon(rect(60.,30.,160.,90.)), level:None, singularities:None},
        Part{name:"r".into(), source: PartSource::Op{op: BoolOp::Subtract, of: vec!["a".into(),"b".into()]}, level:None, singularities:None},
    ];
    let comp = Composition{parts, result:"r".into(), height:None, origin:Vec2::ZERO};
    let built = compose::build(&comp, &mut |_,_| {}).unwrap();
    let f = &built.model.field;
    for y in [0.5, 5., 10., 15., 20., 25., 27., 28., 29., 29.5, 29.9] { print!("x=100 y={y}: {:.1e}  ", f.value(Vec2::new(100.,y))-1.0); }
    println!();
    for x in [60.5, 65., 70., 80., 90., 95., 98., 99., 99.5, 99.9] { print!("y=30 x={x}: {:.1e}  ", f.value(Vec2::new(x,30.))-1.0); }
    println!();
    let ch = built.model.set.material.charges.iter().filter(|q| q.dist(Vec2::new(100.,30.)) < 20.).count();
    println!("charges within 20 of X: {ch}");
    for q in built.model.set.material.charges.iter().filter(|q| q.dist(Vec2::new(100.,30.)) < 20.) { print!("({:.1},{:.1}) ", q.x, q.y); }
    println!();
}
