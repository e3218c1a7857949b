//! The MFS field against what it claims: derivatives, an exact solution, the
//! reported boundary error, and the paper's Table 3.2.

use pfcam::field::{self, mfs, Boundary, Field, Layout, Prepared};
use pfcam::geometry::{Contour, Segment, Vec2};

use crate::common::root;
use crate::doc_figures;

/// A fixed-seed generator (no rand crate needed).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn paper_i_field(n: usize) -> (Prepared, field::Solved) {
    let prep = Prepared::new(field::paper_boundary('I').unwrap()).unwrap();
    let solved = field::solve_auto(&prep, n, None, true).unwrap();
    (prep, solved)
}

#[test]
fn gradient_and_hessian_match_finite_differences() {
    let (prep, solved) = paper_i_field(148);
    let f: &Field = &solved.solution.field;
    let mut rng = Lcg(7);
    let mut checked = 0;
    let mut worst_g: f64 = 0.0;
    let mut worst_h: f64 = 0.0;
    while checked < 200 {
        // Points in the void around the letter (font units), away from the charges.
        let p = Vec2::new(-300.0 + 900.0 * rng.next(), -300.0 + 1300.0 * rng.next());
        if prep.in_material(p) || f.charges().iter().any(|q| q.dist(p) < 20.0) {
            continue;
        }
        checked += 1;
        let h = 1e-3;
        let dx = Vec2::new(h, 0.0);
        let dy = Vec2::new(0.0, h);
        let fd = Vec2::new(
            (f.value(p + dx) - f.value(p - dx)) / (2.0 * h),
            (f.value(p + dy) - f.value(p - dy)) / (2.0 * h),
        );
        let g = f.grad(p);
        let (v, g2) = f.value_grad(p);
        assert!((v - f.value(p)).abs() <= 1e-14 * v.abs().max(1.0));
        assert!((g - g2).norm() <= 1e-14 * g.norm().max(1e-12));
        worst_g = worst_g.max((g - fd).norm() / g.norm().max(1e-12));
        let hs = f.hessian(p);
        let gx = (f.grad(p + dx) - f.grad(p - dx)) / (2.0 * h);
        let gy = (f.grad(p + dy) - f.grad(p - dy)) / (2.0 * h);
        let scale = gx.norm().max(gy.norm()).max(1e-14);
        worst_h = worst_h
            .max((hs[0][0] - gx.x).abs() / scale)
            .max((hs[0][1] - gx.y).abs() / scale)
            .max((hs[1][1] - gy.y).abs() / scale);
        // u is harmonic: the Laplacian by finite differences of u vanishes.
        let lap = (f.value(p + dx) + f.value(p - dx) + f.value(p + dy) + f.value(p - dy)
            - 4.0 * f.value(p))
            / (h * h);
        assert!(
            lap.abs() <= 1e-3 * scale.max(1e-9) + 1e-6,
            "laplacian {lap} at {p:?}"
        );
    }
    assert!(
        worst_g < 1e-6,
        "gradient vs finite differences: {worst_g:e}"
    );
    assert!(worst_h < 1e-5, "hessian vs finite differences: {worst_h:e}");
}

fn circle_contour(c: Vec2, r: f64, ccw: bool) -> Contour {
    // 32 cubic arcs with handles 4/3·tan(θ/4)·r: radial deviation about 1e-10·r.
    let n = 32;
    let th = std::f64::consts::TAU / n as f64;
    let k = 4.0 / 3.0 * (th / 4.0).tan() * r;
    let at = |i: usize| {
        let a = th * i as f64;
        (
            Vec2::new(a.cos(), a.sin()) * r,
            Vec2::new(-a.sin(), a.cos()),
        )
    };
    let segs: Vec<Segment> = (0..n)
        .map(|i| {
            let (a, ta) = at(i);
            let (b, tb) = at(i + 1);
            Segment::Cubic {
                p0: c + a,
                p1: c + a + ta * k,
                p2: c + b - tb * k,
                p3: c + b,
            }
        })
        .collect();
    let contour = Contour::new(segs).unwrap();
    if ccw {
        contour
    } else {
        contour.reversed()
    }
}

#[test]
fn annulus_matches_the_exact_solution() {
    // u = 1 on a circle of radius a, u = 0 on radius R: u = ln(R/r)/ln(R/a).
    let (a, big) = (10.0, 1000.0);
    let b = Boundary {
        contours: vec![circle_contour(Vec2::ZERO, a, true)],
        is_counter: vec![false],
        centre: Vec2::ZERO,
        radius: big,
        flat_tol: 1e-4,
    };
    let prep = Prepared::new(b).unwrap();
    let solved = field::solve_auto(&prep, 80, None, false).unwrap();
    let f = &solved.solution.field;
    assert!(
        solved.solution.max_error < 1e-3,
        "max boundary error {}",
        solved.solution.max_error
    );
    for r in [12.0, 20.0, 50.0, 200.0, 900.0] {
        for k in 0..16 {
            let th = k as f64 * 0.4;
            let p = Vec2::new(r * th.cos(), r * th.sin());
            let exact = (big / r).ln() / (big / a).ln();
            // By the maximum principle the interior error is bounded by the boundary error.
            assert!(
                (f.value(p) - exact).abs() <= solved.solution.max_error * 1.01 + 1e-12,
                "r {r}: {} vs {exact}",
                f.value(p)
            );
        }
    }
}

#[test]
fn reported_max_error_is_the_boundary_maximum() {
    // Sample the glyph boundary independently (20 000 points, every segment) and
    // check that the error found there is not larger than the reported one by more
    // than a small factor: the check points (4 per collocation interval and every
    // corner) must catch the maximum.
    let (prep, solved) = paper_i_field(272);
    let f = &solved.solution.field;
    let c = &prep.boundary.contours[0];
    let mut worst: f64 = 0.0;
    for seg in &c.segments {
        for k in 0..=1000 {
            worst = worst.max((f.value(seg.eval(k as f64 / 1000.0)) - 1.0).abs());
        }
    }
    let reported = solved.solution.max_error;
    assert!(
        worst <= 1.25 * reported,
        "independent max {worst:e} vs reported {reported:e}"
    );
    assert!(
        worst >= 0.5 * reported,
        "reported {reported:e} but independent max only {worst:e}"
    );
}

#[test]
fn table_3_2_is_reproduced_and_beaten() {
    // The paper's Table 3.2 (letter I, M = 2N): every error at most the paper's,
    // and docs/method.md §6's row for that N (M, d, max error, pfcam / paper)
    // is what the solve gives, so the table there cannot drift.
    let paper = [
        (78, 0.921e-2),
        (148, 0.504e-2),
        (272, 0.871e-3),
        (396, 0.413e-3),
        (516, 0.255e-3),
    ];
    let ns: Vec<usize> = paper.iter().map(|p| p.0).collect();
    let rows = field::convergence_table('I', &ns).unwrap();
    let doc = doc_figures::read("docs/method.md");
    let table = doc_figures::after(&doc, "docs/method.md", "## 6. Table 3.2");
    for (row, (n, err)) in rows.iter().zip(paper) {
        assert_eq!(row.n, n);
        assert_eq!(row.m, 2 * n);
        assert!(
            row.max_error <= err,
            "N = {n}: {:e} > paper {err:e}",
            row.max_error
        );
        let cells = doc_figures::table_row(table, "docs/method.md", &n.to_string());
        let what = format!("docs/method.md §6, N = {n}");
        assert_eq!(cells[1].parse::<usize>().ok(), Some(row.m), "{what}: M");
        doc_figures::assert_figure(&what, cells[2], row.distance);
        doc_figures::assert_figure(&what, cells[3], row.max_error);
        doc_figures::assert_figure(&what, cells[5], row.max_error / err);
    }
}

#[test]
fn fixed_distance_is_used_as_given() {
    let prep = Prepared::new(field::paper_boundary('I').unwrap()).unwrap();
    let s = field::solve_auto(&prep, 148, Some(5.0), true).unwrap();
    assert_eq!(s.layout.distance, 5.0);
    assert_eq!(s.solves, 1);
    let (sol, m) = field::solve_layout(
        &prep,
        &Layout {
            distance: 5.0,
            ..s.layout
        },
    )
    .unwrap();
    assert_eq!(m, 296);
    assert_eq!(sol.max_error, s.solution.max_error);
}

#[test]
fn too_few_singularities_is_a_typed_error() {
    let prep = Prepared::new(field::paper_boundary('A').unwrap()).unwrap();
    let e = field::solve_auto(&prep, 10, None, true).unwrap_err();
    assert!(e.to_string().contains("too few"), "{e}");
}

#[test]
fn kernel_is_the_fundamental_solution() {
    let p = Vec2::new(3.0, 4.0);
    assert!((mfs::kernel(p, Vec2::ZERO) + 5f64.ln() / std::f64::consts::TAU).abs() < 1e-15);
}

/// The shape field of a profile job with `svg_path` at `origin`.
fn shape_error(svg_path: &str, origin: [f64; 2]) -> f64 {
    let shape = format!(
        "svg_path = \"{svg_path}\"\norigin = [{}, {}]",
        origin[0], origin[1]
    );
    profile_field(&shape).0
}

/// The max boundary error and N of the shape field of a profile job whose
/// `[shape]` table is `shape` (paths relative to the crate root).
fn profile_field(shape: &str) -> (f64, usize) {
    let text = format!("[shape]\n{shape}\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 1.0\n");
    let root = root();
    let job = pfcam::job::parse_job(&text, "shape", root).unwrap();
    let (shape_, _) = pfcam::pipeline::job_shape(&job, &mut |_| {}).unwrap();
    let tol = job.operation.tolerance * pfcam::pipeline::FLATTEN_FRACTION;
    let (_, report, _) = pfcam::pipeline::solve_shape(&shape_, &job, tol, &mut |_| {})
        .unwrap_or_else(|e| panic!("{shape}: {e}"));
    (report.max_error, report.n)
}

/// docs/method.md §2: "Hello" in DejaVu Serif, a profile job at the default
/// N, solves to the error and N it quotes.
#[test]
fn hello_in_dejavu_serif_solves_as_the_docs_say() {
    let (error, n) = profile_field("text = \"Hello\"\nfont = \"tests/data/DejaVuSerif.ttf\"");
    eprintln!("Hello in DejaVu Serif: max boundary error {error:.2e} at N = {n}");
    let doc = doc_figures::read("docs/method.md");
    let stated = doc_figures::numbers_after(
        &doc,
        "docs/method.md",
        "\"Hello\" in DejaVu Serif solves to",
        2,
    );
    doc_figures::assert_figure("docs/method.md §2, Hello", &stated[0], error);
    assert_eq!(
        stated[1].parse().ok(),
        Some(n),
        "docs/method.md §2, Hello's N"
    );
}

/// Issue 12: a plain rectangle and an L shape were refused as ill-conditioned
/// ("condition number inf"), and whether a rectangle was refused depended on
/// where it sat. They solve, wherever they sit, with the same error.
#[test]
fn rectangles_and_l_shapes_solve_wherever_they_sit() {
    let mut errors = Vec::new();
    for path in [
        "M0 0 L10 0 L10 40 L0 40 Z",
        "M0 0 L10.1 0 L10.1 40 L0 40 Z",
        "M0 0 L9.9 0 L9.9 40 L0 40 Z",
        "M0 0 L30 0 L30 10 L10 10 L10 40 L0 40 Z",
    ] {
        let here = shape_error(path, [0.0, 0.0]);
        let there = shape_error(path, [13.7, -5.3]);
        eprintln!("{path}: {here:.2e} at [0, 0], {there:.2e} at [13.7, -5.3]");
        errors.push((here, there));
        assert!(
            here < 1e-3 && there < 1e-3,
            "{path}: {here:.2e}, {there:.2e}"
        );
        assert!(
            there <= 2.0 * here && here <= 2.0 * there,
            "{path}: {here:.2e} at the origin, {there:.2e} moved"
        );
    }
    // docs/method.md §2 quotes the 10 × 40 rectangle (both origins) and the L.
    let doc = doc_figures::read("docs/method.md");
    let stated = doc_figures::numbers_after(&doc, "docs/method.md", "they now solve to", 2);
    let what = "docs/method.md §2, rectangle and L";
    doc_figures::assert_figure(what, &stated[0], errors[0].0);
    doc_figures::assert_figure(what, &stated[0], errors[0].1);
    doc_figures::assert_figure(what, &stated[1], errors[3].0);
}

/// The fast evaluator (`field::fast`, local expansions of the far charges)
/// against the direct sums, on the paper's S and A (its counter has a sink)
/// solved as the pipeline solves them: random points around the glyph and
/// points within one charge spacing of its boundary. Issue 13's bound: the
/// differences at most 1e-12 of the largest |u| and |∇u| seen.
#[test]
fn local_expansions_match_the_direct_sums() {
    use field::adaptive::{solve_to, Target};
    let mut measured = Vec::new();
    for ch in ['S', 'A'] {
        let prep = Prepared::new(field::paper_boundary(ch).unwrap()).unwrap();
        let target = Target {
            max_error: 0.0,
            n_start: 1000,
            n_max: 1000,
            distance: None,
        };
        let direct = solve_to(&prep, &target).unwrap().solution.field;
        let polys = prep.polygons();
        let (mut lo, mut hi) = (polys[0][0], polys[0][0]);
        for p in polys.iter().flatten() {
            lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        let diag = (hi - lo).norm();
        let pad = Vec2::new(0.5 * diag, 0.5 * diag);
        let fast = direct.accelerated(lo - pad, hi + pad, diag / 100.0);
        let h = prep.perimeter() / 1000.0;
        let mut rng = Lcg(7);
        let mut points = Vec::new();
        while points.len() < 3000 {
            let p = Vec2::new(
                lo.x - pad.x + (hi.x - lo.x + 2.0 * pad.x) * rng.next(),
                lo.y - pad.y + (hi.y - lo.y + 2.0 * pad.y) * rng.next(),
            );
            if !prep.in_material(p) {
                points.push(p);
            }
        }
        for poly in polys {
            for w in poly.windows(2).step_by(3) {
                let m = w[0].lerp(w[1], rng.next());
                let off = Vec2::new(rng.next() - 0.5, rng.next() - 0.5) * (2.0 * h);
                if !prep.in_material(m + off) {
                    points.push(m + off);
                }
            }
        }
        let (mut du, mut dg, mut umax, mut gmax) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for &p in &points {
            let (u0, g0) = direct.value_grad(p);
            let (u1, g1) = fast.value_grad(p);
            assert_eq!(fast.value(p), u1, "value and value_grad agree");
            umax = umax.max(u0.abs());
            gmax = gmax.max(g0.norm());
            du = du.max((u1 - u0).abs());
            dg = dg.max((g1 - g0).norm());
        }
        // `Field::values` gives `value`'s bits, on the random points (box
        // by box apart) and on rows 0.05·h apart (four to a box, side by
        // side), 1001 a row so the last run is short; direct fields too.
        let mut rows = points.clone();
        for k in 0..6 {
            let y = lo.y + (hi.y - lo.y) * (k as f64 + 0.5) / 6.0;
            rows.extend((0..1001).map(|i| Vec2::new(lo.x - pad.x + 0.05 * h * i as f64, y)));
        }
        for f in [&fast, &direct] {
            let mut batch = vec![0.0; rows.len()];
            f.values(&rows, &mut batch);
            for (&p, v) in rows.iter().zip(&batch) {
                assert_eq!(v.to_bits(), f.value(p).to_bits(), "{ch}: values at {p:?}");
            }
            // Lengths that do not match fill what both cover, and no more.
            let mut short = vec![-1.0; 7];
            f.values(&rows[1000..1010], &mut short);
            assert_eq!(short[6].to_bits(), f.value(rows[1006]).to_bits());
            let mut long = vec![-1.0; 9];
            f.values_where(&mut long, &[false; 6], |i| rows[1000 + i]);
            assert_eq!(long[5].to_bits(), f.value(rows[1005]).to_bits());
            assert_eq!(long[6..], [-1.0; 3]);
        }
        assert!(du <= 1e-12 * umax, "{ch}: |Δu| {du:e}, max |u| {umax}");
        assert!(dg <= 1e-12 * gmax, "{ch}: |Δ∇u| {dg:e}, max |∇u| {gmax}");
        eprintln!(
            "{ch}: {} points, |Δu| ≤ {du:.1e} (max |u| {umax:.3}), |Δ∇u| ≤ {dg:.1e} (max |∇u| {gmax:.3e})",
            points.len()
        );
        measured.push((du, dg, dg / gmax));
    }
    // docs/method.md §12: |Δu| on S and on A, then the largest |Δ∇u|, absolute
    // and as a share of max |∇u|.
    let doc = doc_figures::read("docs/method.md");
    let stated = doc_figures::numbers_after(&doc, "docs/method.md", "|u_fast − u_direct| ≤", 4);
    let what = "docs/method.md §12, local expansions against direct sums";
    doc_figures::assert_figure(what, &stated[0], measured[0].0);
    doc_figures::assert_figure(what, &stated[1], measured[1].0);
    let worst = |f: fn(&(f64, f64, f64)) -> f64| measured.iter().map(f).fold(0.0, f64::max);
    doc_figures::assert_figure(what, &stated[2], worst(|m| m.1));
    doc_figures::assert_figure(what, &stated[3], worst(|m| m.2));
}

#[allow(dead_code)] // its `main` is the example's command line
#[path = "../../examples/ring_charges.rs"]
mod ring_charges;

/// docs/method.md §3 and §3a say what a ring with fewer charges leaves on its
/// circle, measured by `examples/ring_charges.rs`: the same measurement here
/// must give the doc's figures.
#[test]
fn ring_charge_counts_leave_what_the_docs_say() {
    let doc = doc_figures::read("docs/method.md");
    let on_ring = |ch, n, pairs, outer, counts: &[usize]| -> Vec<f64> {
        let (_, _, solves) = ring_charges::measure(ch, n, pairs, outer, counts);
        solves.iter().map(|s| s.on_ring).collect()
    };
    // §3: the plain layout's outer ring with 4 charges, letter I, N = 516.
    let plain = on_ring('I', 516, false, true, &[4, 8]);
    for (marker, value) in [
        ("4 charges left a floor of", plain[0]),
        ("(8 leave", plain[1]),
    ] {
        let stated = doc_figures::number_after(&doc, "docs/method.md", marker);
        doc_figures::assert_figure("docs/method.md §3, outer ring", &stated, value);
    }
    // §3a: the paired layout's outer ring of 8 and of 16, letter I, N = 800.
    let paired = on_ring('I', 800, true, true, &[8, 16]);
    for (marker, value) in [("8 left a floor of", paired[0]), ("16 give", paired[1])] {
        let stated = doc_figures::number_after(&doc, "docs/method.md", marker);
        doc_figures::assert_figure("docs/method.md §3a, outer ring", &stated, value);
    }
    // §3a: the letter A's sink ring of 6 charges, N = 396.
    let sink = on_ring('A', 396, true, false, &[6]);
    let stated =
        doc_figures::number_after(&doc, "docs/method.md", "with 6, the letter A stayed at");
    doc_figures::assert_figure("docs/method.md §3a, sink ring of 6", &stated, sink[0]);
}

/// docs/method.md §6: without corner clusters (f = 0, the plain layout) the
/// distance search of §4 leaves the letter I at the errors it quotes
/// (`cargo run --release --example conv -- I 0 78,148,272`).
#[test]
fn uniform_placement_errors_are_the_docs() {
    let doc = doc_figures::read("docs/method.md");
    let stated =
        doc_figures::numbers_after(&doc, "docs/method.md", "(f = 0), the same search gives", 3);
    let prep = Prepared::new(field::paper_boundary('I').unwrap()).unwrap();
    for (figure, n) in stated.iter().zip([78, 148, 272]) {
        let uniform = Layout {
            n_total: n,
            distance: 1.0,
            corner_clusters: false,
            corner_fraction: 0.0,
            pairs: false,
        };
        let solved = field::solve_with(&prep, uniform, None).unwrap();
        let what = format!("docs/method.md §6, uniform placement at N = {n}");
        doc_figures::assert_figure(&what, figure, solved.solution.max_error);
    }
}
