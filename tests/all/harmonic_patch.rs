//! A harmonic patch as a job's part (`shape.kind = "harmonic-bezier"`): its
//! sections against analytic areas and an independent pixel count, their
//! orientation and their vertices on {h = z}; the job's errors naming keys.

use pfcam::geometry::Vec2;
use pfcam::job::{parse_job, Job};
use pfcam::levels::sections::{net_area, Sections};
use pfcam::pipeline;
use std::path::Path;

fn job(body: &str) -> Result<Job, String> {
    parse_job(body, "patch", Path::new(".")).map_err(|e| e.to_string())
}

/// A patch job with these `[shape]` lines after `kind`.
fn patch_job(shape: &str) -> String {
    format!(
        "[shape]\nkind = \"harmonic-bezier\"\n{shape}\n[tool]\ndiameter = 6.0\nstepdown = 1.5\n\
         [operation]\ntolerance = 0.01\nmax_scallop = 50.0\n"
    )
}

fn sections(j: &Job) -> Box<dyn Sections> {
    pipeline::job_sections(j, &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// h = 10 (x/X)(y/Y) (degree 1: row0 = [0, 0], row1 = [0, 10]) is harmonic
/// in the parameters; {h ≥ 10t} has area XY (1 − t + t ln t) (the region
/// above the hyperbola uv = t in the unit square).
#[test]
fn a_bilinear_saddle_has_the_analytic_area() {
    let j = job(&patch_job(
        "degree = 1\nsize = [80.0, 60.0]\nrow0 = [0.0, 0.0]\nrow1 = [0.0, 10.0]\norigin = [5.0, -3.0]",
    ))
    .unwrap();
    assert!(
        (j.operation.depth - 10.0).abs() < 1e-12,
        "{}",
        j.operation.depth
    );
    let s = sections(&j);
    assert_eq!(s.z_range(), (-10.0, 0.0));
    for t in [0.05, 0.2, 0.5, 0.8, 0.95] {
        let sec = s.section(10.0 * t - 10.0);
        let exact = 4800.0 * (1.0 - t + t * f64::ln(t));
        let area = net_area(&sec);
        assert!(
            (area - exact).abs() < 1e-4 * 4800.0,
            "t {t}: {area} against {exact}"
        );
        assert_eq!(sec.len(), 1, "t {t}: one region");
        // The corner (X, Y) is in it, and the region is to the left.
        assert!(sec[0].iter().any(|p| p.dist(Vec2::new(85.0, 57.0)) < 1e-9));
        assert!(area > 0.0);
    }
    // The bottom is the whole rectangle, the top the corner.
    assert!((net_area(&s.section(-10.0)) - 4800.0).abs() < 1e-9);
    let top = s.section(0.0);
    assert!(top[0][0].dist(Vec2::new(85.0, 57.0)) < 1e-9, "{top:?}");
}

/// Re (u + iv)³ = u³ − 3uv², scaled to 12 mm, degree 3: its sections'
/// areas against a pixel count of {h ≥ z} on a 0.05 mm grid (h evaluated by
/// the polynomial itself, not the patch), and every vertex on {h = z} or on
/// the border with h ≥ z.
#[test]
fn sections_of_a_cubic_match_a_pixel_count() {
    use pfcam::sources::harmonic_bezier::polynomials::{bernstein_net, eval, re_im_power};
    let p: Vec<(usize, usize, f64)> = re_im_power(3, false)
        .into_iter()
        .map(|(a, b, c)| (a, b, 6.0 * c))
        .collect();
    let net = bernstein_net(&p, 3, 3);
    let row = |i: usize| -> String {
        let r: Vec<String> = net[i * 4..i * 4 + 4]
            .iter()
            .map(|h| format!("{h:?}"))
            .collect();
        format!("[{}]", r.join(", "))
    };
    let (sx, sy) = (40.0, 30.0);
    let j = job(&patch_job(&format!(
        "degree = 3\nsize = [{sx}, {sy}]\nrow0 = {}\nrow1 = {}",
        row(0),
        row(3)
    )))
    .unwrap();
    // u = y / Y across the rows, v = x / X along them.
    let h = |x: f64, y: f64| eval(&p, y / sy, x / sx);
    let s = sections(&j);
    let (bottom, top) = s.z_range();
    let (hmin, hmax) = (-12.0, 6.0);
    assert!(
        (top - bottom - (hmax - hmin)).abs() < 1e-9,
        "{bottom} {top}"
    );
    let px = 0.05;
    let (nx, ny) = ((sx / px) as usize, (sy / px) as usize);
    for frac in [0.1, 0.3, 0.5, 0.7, 0.9] {
        let z = bottom + frac * (top - bottom);
        let level = hmax + z;
        let sec = s.section(z);
        let count = (0..nx * ny)
            .filter(|k| {
                let (x, y) = ((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
                h(x * px, y * px) >= level
            })
            .count();
        let pixels = count as f64 * px * px;
        let area = net_area(&sec);
        assert!(
            (area - pixels).abs() < 2e-3 * sx * sy,
            "z {z}: {area} against {pixels} by pixels"
        );
        for poly in &sec {
            assert!(
                pfcam::geometry::polygon_area(poly) > 0.0,
                "outlines run CCW"
            );
            for q in poly {
                let on_border = q.x.abs() < 1e-9
                    || q.y.abs() < 1e-9
                    || (q.x - sx).abs() < 1e-9
                    || (q.y - sy).abs() < 1e-9;
                let e = h(q.x, q.y) - level;
                assert!(
                    e.abs() < 1e-7 || (on_border && e > -1e-7),
                    "z {z}: vertex {q:?} has h − z = {e}"
                );
            }
        }
    }
}

#[test]
fn patch_errors_name_their_keys() {
    let base = "degree = 3\nsize = [80.0, 60.0]\nrow0 = [0.0, 14.0, 2.0, 10.0]\nrow1 = [8.0, -2.0, 12.0, 4.0]";
    assert!(job(&patch_job(base)).is_ok());
    let cases: &[(&str, &str, &str)] = &[
        (
            "degree = 3",
            "degree = 11",
            "shape.degree 11 is above the cap 10",
        ),
        (
            "degree = 3",
            "degree = 0",
            "shape.degree must be an integer ≥ 1",
        ),
        (
            "row0 = [0.0, 14.0, 2.0, 10.0]",
            "row0 = [1.0, 2.0]",
            "shape.row0 degree 3 needs 4 heights",
        ),
        (
            "row1 = [8.0, -2.0, 12.0, 4.0]",
            "row1 = [8.0, nan, 12.0, 4.0]",
            "shape.row1[1]",
        ),
        (
            "degree = 3",
            "degree = 3\nform = \"raised\"",
            "shape.form the raised",
        ),
        (
            "degree = 3",
            "degree = 3\ntext = \"I\"",
            "shape.text does not apply",
        ),
        (
            "size = [80.0, 60.0]",
            "size = [80.0, 0.0]",
            "shape.size must be",
        ),
    ];
    for (from, to, want) in cases {
        let body = patch_job(&base.replace(from, to));
        let e = job(&body).unwrap_err();
        assert!(e.contains(want), "{to}: {e}");
    }
    let flat = base
        .replace("[0.0, 14.0, 2.0, 10.0]", "[8.0, 8.0, 8.0, 8.0]")
        .replace("[8.0, -2.0, 12.0, 4.0]", "[8.0, 8.0, 8.0, 8.0]");
    let e = job(&patch_job(&flat)).unwrap_err();
    assert!(
        e.contains("shape.row0 and shape.row1 make a flat patch"),
        "{e}"
    );
    // Even degree, square form: the rows' 4-th differences must agree.
    let even = patch_job(
        "degree = 4\nform = \"square\"\nsize = [80.0, 60.0]\nrow0 = [0, 5, 9, 5, 0]\nrow1 = [0, 3, 3, 3, 1]",
    );
    let e = job(&even).unwrap_err();
    assert!(
        e.contains("shape.row0, shape.row1") && e.contains("4-th differences"),
        "{e}"
    );
    assert!(job(&even.replace("\"square\"", "\"raised\"")).is_ok());
    // Keys of the other tables.
    let with = |extra: &str| job(&format!("{}{extra}", patch_job(base))).unwrap_err();
    assert!(with("depth = 3.0\n").contains("operation.depth = 3 does not apply"));
    assert!(with("kind = \"cavity\"\n").contains("negate shape.row0"));
    assert!(with("kind = \"profile\"\n").contains("operation.kind"));
    assert!(with("[profile]\nkind = \"linear\"\n").starts_with("profile does not apply"));
    // Patch keys without kind.
    let e =
        job("[shape]\ntext = \"I\"\ndegree = 3\n[tool]\ndiameter = 3\n[operation]\ndepth = 1\n")
            .unwrap_err();
    assert!(e.contains("shape.degree only applies"), "{e}");
    let e = job(&patch_job(base).replace("harmonic-bezier", "coons")).unwrap_err();
    assert!(e.contains("shape.kind"), "{e}");
}

/// The part's closed mesh: watertight, and its volume that of the block
/// under the surface. For the ramp h = 10 x / X (degree 1), with the top at
/// max h = 10 and the bottom `BASE_THICKNESS` below min h, the block is
/// X Y (mean h − max h + depth + base) = 4800 × (5 − 10 + 10 + 2) exactly (a
/// plane is triangulated exactly); the cubic's against a midpoint-rule mean.
#[test]
fn the_part_mesh_is_closed_and_has_the_blocks_volume() {
    use pfcam::surface::{job_part_surface, SurfaceOptions, BASE_THICKNESS};
    let opts = SurfaceOptions { resolution: 0.5 };
    let ramp = job(&patch_job(
        "degree = 1\nsize = [80.0, 60.0]\nrow0 = [0.0, 10.0]\nrow1 = [0.0, 10.0]",
    ))
    .unwrap();
    let s = job_part_surface(&ramp, &opts, &mut |_| {}).unwrap();
    s.mesh.check().unwrap();
    let v = s.mesh.volume();
    let exact = 4800.0 * (5.0 - 10.0 + 10.0 + BASE_THICKNESS);
    assert!((v - exact).abs() < 1e-6 * exact, "{v} against {exact}");
    let cubic = job(&patch_job(
        "degree = 3\nsize = [80.0, 60.0]\nrow0 = [0.0, 14.0, 2.0, 10.0]\nrow1 = [8.0, -2.0, 12.0, 4.0]\n\
         origin = [10.0, 20.0]",
    ))
    .unwrap();
    let s = job_part_surface(&cubic, &opts, &mut |_| {}).unwrap();
    s.mesh.check().unwrap();
    let sec = sections(&cubic);
    let (bottom, _) = sec.z_range();
    let pfcam::geometry::ShapeSource::HarmonicBezier(spec) = &cubic.shape else {
        panic!("a patch");
    };
    let patch = spec.patch().unwrap();
    let hmax = patch.height_range().max;
    let n = 400;
    let mean: f64 = (0..n * n)
        .map(|k| {
            let (x, y) = (
                ((k % n) as f64 + 0.5) / n as f64,
                ((k / n) as f64 + 0.5) / n as f64,
            );
            patch.height(80.0 * x, 60.0 * y)
        })
        .sum::<f64>()
        / (n * n) as f64;
    let exact = 4800.0 * (mean - hmax - bottom + BASE_THICKNESS);
    let v = s.mesh.volume();
    assert!((v - exact).abs() < 1e-3 * exact, "{v} against {exact}");
    let (lo, hi) = s.mesh.bbox().unwrap();
    assert_eq!((lo[0], lo[1], hi[0], hi[1]), (10.0, 20.0, 90.0, 80.0));
    // The top is max h at the stock top (0), which a grid vertex meets only
    // where the maximum falls on one: within what h changes over a cell.
    assert!(hi[2] <= 1e-9 && hi[2] > -0.05, "{}", hi[2]);
    assert!((lo[2] - (bottom - BASE_THICKNESS)).abs() < 1e-9);
}

/// jobs/harmonic-patch.toml, roughed then finished, simulated by the binary
/// against the patch: no finding, the largest gouge within the tolerance,
/// and the material the ball can reach left within the scallop + 0.01 mm.
#[test]
fn the_shipped_patch_simulates_clean() {
    let v = crate::common::run_and_simulate("harmonic_patch", "harmonic-patch");
    let part = &v["part"];
    assert_eq!(part["model"], "harmonic patch");
    crate::common::assert_within_part(part, 0.01, 0.01 + 0.01);
}

/// A flat finisher is refused: its edge leaves a stair on a curved surface.
#[test]
fn a_flat_finisher_is_refused_for_a_patch() {
    let body = format!(
        "{}[finish]\nshape = \"flat\"\ndiameter = 3.0\n",
        patch_job("degree = 1\nsize = [20.0, 20.0]\nrow0 = [0.0, 5.0]\nrow1 = [0.0, 5.0]")
    );
    let j = job(&body).unwrap();
    let e = pipeline::run(&j, &mut |_| {}).unwrap_err().to_string();
    assert!(e.contains("finish.shape = \"flat\""), "{e}");
}
