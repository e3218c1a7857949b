//! Speed benchmarks (criterion). Run: `cargo bench --bench pfcam`.
//! Figures reported in docs/method.md are the medians criterion prints.

use criterion::{criterion_group, criterion_main, Criterion};
use pfcam::field::{self, Boundary, Layout, Prepared};
use pfcam::geometry::Vec2;
use std::hint::black_box;

fn letter_i_solve(c: &mut Criterion) {
    let prep = Prepared::new(field::paper_boundary('I').unwrap()).unwrap();
    let layout = Layout {
        n_total: 516,
        distance: 5.0,
        corner_clusters: true,
        corner_fraction: field::DEFAULT_CORNER_FRACTION,
        pairs: false,
    };
    c.bench_function("letter I: one MFS solve, N = 516, M = 1032", |b| {
        b.iter(|| field::solve_layout(&prep, black_box(&layout)).unwrap())
    });
    let mut g = c.benchmark_group("slow");
    g.sample_size(10);
    g.bench_function(
        "letter I: solve with the distance chosen (17 solves), N = 516",
        |b| b.iter(|| field::solve_auto(&prep, black_box(516), None, true).unwrap()),
    );
    g.finish();
}

/// The paper's MFS string in font units (F and S shifted by D1 = 1300, D2 = 2200).
fn mfs_boundary() -> Boundary {
    let mut contours = Vec::new();
    for (ch, dx) in [('M', 0.0), ('F', 1300.0), ('S', 2200.0)] {
        let g = pfcam::geometry::glyphs::paper_glyph(ch).unwrap();
        contours.extend(
            g.outlines
                .iter()
                .map(|o| o.map(move |p| Vec2::new(p.x + dx, p.y))),
        );
    }
    let centre = field::centroid(&contours, 0.01);
    let is_counter = vec![false; contours.len()];
    Boundary {
        contours,
        is_counter,
        centre,
        radius: 1e4,
        flat_tol: 0.01,
    }
}

fn field_eval(c: &mut Criterion) {
    let prep = Prepared::new(mfs_boundary()).unwrap();
    let layout = Layout {
        n_total: 1210,
        distance: 8.0,
        corner_clusters: true,
        corner_fraction: field::DEFAULT_CORNER_FRACTION,
        pairs: false,
    };
    let (sol, _) = field::solve_layout(&prep, &layout).unwrap();
    let f = sol.field;
    assert_eq!(f.n(), 1210);
    let p = Vec2::new(1000.0, 720.0);
    c.bench_function("field: u and grad u at one point, N = 1210", |b| {
        b.iter(|| f.value_grad(black_box(p)))
    });
    c.bench_function("field: grad u at one point, N = 1210", |b| {
        b.iter(|| f.grad(black_box(p)))
    });
}

fn job(path: &str) -> pfcam::job::Job {
    pfcam::job::load_job(std::path::Path::new(path)).unwrap()
}

fn profiles(c: &mut Criterion) {
    let mut g = c.benchmark_group("jobs");
    g.sample_size(10);
    let i = job("jobs/letter-i.toml");
    g.bench_function(
        "letter I profile (solve + trace + gouge check), tol 0.01 mm",
        |b| b.iter(|| pfcam::pipeline::run(black_box(&i), &mut |_| {}).unwrap()),
    );
    let mfs = job("jobs/mfs-profile.toml");
    g.bench_function(
        "mfs-profile end to end (solve + trace + arcs + check + G-code)",
        |b| {
            b.iter(|| {
                let out = pfcam::pipeline::run(black_box(&mfs), &mut |_| {}).unwrap();
                pfcam::gcode::write_gcode(&out.toolpath, &mfs).unwrap()
            })
        },
    );
    g.finish();
}

fn levels(c: &mut Criterion) {
    let mut g = c.benchmark_group("levels");
    g.sample_size(10);
    let sign = job("jobs/mfs-sign.toml");
    g.bench_function(
        "mfs-sign boss, 40 levels, end to end (solves, levels, tracing, clearing, arcs, check)",
        |b| b.iter(|| pfcam::pipeline::run(black_box(&sign), &mut |_| {}).unwrap()),
    );
    // The full mould: about 40 s a run, so this group alone takes about 8 minutes.
    let full_mould = job("jobs/mfs-mould.toml");
    g.bench_function("mfs-mould cavity, 26 levels, end to end", |b| {
        b.iter(|| pfcam::pipeline::run(black_box(&full_mould), &mut |_| {}).unwrap())
    });
    // The same code on the letter I's mould, quick enough to run often.
    let mould = pfcam::job::parse_job(
        "[shape]\ntext = \"I\"\nheight = 50.0\n[tool]\ndiameter = 3.175\nstepdown = 1.0\n\
         [operation]\nkind = \"cavity\"\ndepth = 2.0\nmax_scallop = 2.0\n[profile]\nkind = \"linear\"\ns_bottom = 0.97\n",
        "i-mould",
        std::path::Path::new("."),
    )
    .unwrap();
    g.bench_function("letter I mould (cavity), end to end", |b| {
        b.iter(|| pfcam::pipeline::run(black_box(&mould), &mut |_| {}).unwrap())
    });
    g.finish();
}

/// `pfcam surface` on mfs-sign without its field solve (benched above): stock,
/// grid, level crossings, isobands, walls and bottom.
fn surface(c: &mut Criterion) {
    let sign = job("jobs/mfs-sign.toml");
    let (shape, _) = pfcam::pipeline::job_shape(&sign, &mut |_| {}).unwrap();
    let flat_tol = sign.operation.tolerance * pfcam::pipeline::FLATTEN_FRACTION;
    let (solved, _, _) =
        pfcam::pipeline::solve_shape(&shape, &sign, flat_tol, &mut |_| {}).unwrap();
    let glyphs: Vec<Vec<Vec2>> = shape.contours().map(|c| c.flatten(flat_tol)).collect();
    let sj = pfcam::surface::SurfaceJob {
        field: &solved.solution.field,
        glyphs: &glyphs,
        profile: sign.profile.as_ref().unwrap(),
        cavity: false,
        top: sign.stock.top,
        margin: sign.stock.margin,
        tol: sign.operation.tolerance,
    };
    let opts = pfcam::surface::SurfaceOptions::default();
    let mut g = c.benchmark_group("surface");
    g.sample_size(10);
    g.bench_function(
        "mfs-sign surface mesh (0.4 mm grid, field solved once)",
        |b| b.iter(|| pfcam::surface::build(black_box(&sj), &opts, &mut |_| {}).unwrap()),
    );
    g.finish();
}

/// The paper's letter Q: its composition alone (eight MFS solves), and the whole
/// boss and mould jobs.
fn letter_q(c: &mut Criterion) {
    let sign = job("jobs/q-sign.toml");
    let mould = job("jobs/q-mould.toml");
    let mut g = c.benchmark_group("letter Q");
    g.sample_size(10);
    g.bench_function("Q from its parts (m1..m6, Q: eight solves)", |b| {
        b.iter(|| pfcam::pipeline::job_shape(black_box(&sign), &mut |_| {}).unwrap())
    });
    g.bench_function("q-sign boss, end to end", |b| {
        b.iter(|| pfcam::pipeline::run(black_box(&sign), &mut |_| {}).unwrap())
    });
    g.bench_function("q-mould cavity, end to end", |b| {
        b.iter(|| pfcam::pipeline::run(black_box(&mould), &mut |_| {}).unwrap())
    });
    g.finish();
}

/// `pfcam simulate` of the largest sample (124 260 lines, 250 m of feed) at 0.1 mm cells.
fn simulate_mould(c: &mut Criterion) {
    let text = std::fs::read_to_string("gcode-samples/mfs-mould.nc").unwrap();
    let opts = pfcam::simulate::SimOptions::default();
    let mut g = c.benchmark_group("simulate");
    g.sample_size(10);
    g.bench_function("simulate mfs-mould.nc at 0.1 mm", |b| {
        b.iter(|| pfcam::simulate::simulate(black_box(&text), &opts).unwrap())
    });
    g.finish();
}

criterion_group!(
    benches,
    simulate_mould,
    letter_i_solve,
    field_eval,
    profiles,
    levels,
    surface,
    letter_q
);
criterion_main!(benches);
