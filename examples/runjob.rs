use pfcam::geometry::{FontSource, ShapeSource, Vec2};
use pfcam::job::*;
fn main() {
    let text = std::env::args().nth(1).unwrap_or("MFS".into());
    let job = Job {
        name: "t".into(),
        shape: ShapeSource::Text {
            text,
            font: FontSource::Paper,
            height: 50.0,
            letter_spacing: 2.0,
            origin: Vec2::ZERO,
        },
        tool: Tool {
            diameter: 3.175,
            feed: 800.0,
            plunge_feed: 200.0,
            spindle: 18000.0,
            stepdown: 3.0,
        },
        stock: Stock {
            top: 0.0,
            safe_z: 5.0,
        },
        operation: Operation {
            kind: OperationKind::Profile,
            side: Side::Outside,
            depth: 3.0,
            tolerance: 0.01,
            direction: Direction::Climb,
        },
        field: FieldSpec::default(),
        machine: Machine::default(),
        output: Output::default(),
    };
    let t = std::time::Instant::now();
    let out = pfcam::pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    println!("{:?}", t.elapsed());
    println!("{:?}", out.solves);
    println!(
        "clearance {:e} moves {} warnings {:?}",
        out.min_clearance,
        out.toolpath.moves().count(),
        out.warnings
    );
    println!("{:?}", out.toolpath.stats(3000.0));
}
