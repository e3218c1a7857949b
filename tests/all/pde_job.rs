//! A PDE tube as a job's part (`shape.kind = "pde-tube"`, docs/method.md
//! §16.3 "As a job"): its sections against the squircle's and the circle's
//! exact areas and against a tube built independently from the same curves;
//! the mould as the boss upside down; errors naming their keys; the part's
//! closed mesh; the shipped job simulated clean.

use pfcam::geometry::{ShapeSource, Vec2};
use pfcam::job::{parse_job, Job};
use pfcam::levels::sections::{net_area, Sections};
use pfcam::pipeline;
use pfcam::sources::pde::BoundaryCurves;
use pfcam::sources::pde_tube::{PdeTube, TubeKind};
use std::f64::consts::{PI, TAU};
use std::path::Path;

fn job(body: &str) -> Result<Job, String> {
    parse_job(body, "tube", Path::new(".")).map_err(|e| e.to_string())
}

/// The vase as `[shape]` lines: the squircle |x|⁴ + |y|⁴ = 10⁴ at
/// the foot, a circle of radius 6 at the top, 15 mm up.
const VASE: &str =
    "bottom_size = [20.0, 20.0]\nbottom_exponent = 4.0\ntop_size = [12.0, 12.0]\nheight = 15.0\n";

/// A tube job with these `[shape]` lines after `kind`, and `extra` after
/// `[operation]`.
fn tube_job(shape: &str, extra: &str) -> String {
    format!(
        "[shape]\nkind = \"pde-tube\"\n{shape}\n[tool]\ndiameter = 3.175\nstepdown = 1.0\n\
         [operation]\ntolerance = 0.01\n{extra}"
    )
}

fn sections(j: &Job) -> Box<dyn Sections> {
    pipeline::job_sections(j, &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// 4·10²·Γ(5/4)²/Γ(3/2), the area inside |x|⁴ + |y|⁴ = 10⁴ (mm²): Γ(5/4) =
/// 0.9064024770554771, Γ(3/2) = √π/2.
const SQUIRCLE_AREA: f64 = 370.8149354602745;

/// The squircle's area by an independent route: ½∮r(θ)²dθ with r(θ) =
/// 10 (cos⁴θ + sin⁴θ)^(−1/4), by the trapezoid rule on 200 000 points
/// (exponentially accurate for a smooth periodic integrand).
fn squircle_area_by_quadrature() -> f64 {
    let n = 200_000;
    (0..n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            let r = 10.0 / (t.cos().powi(4) + t.sin().powi(4)).powf(0.25);
            0.5 * r * r * TAU / n as f64
        })
        .sum()
}

/// A polygon's perimeter, mm.
fn perimeter(p: &[Vec2]) -> f64 {
    (0..p.len()).map(|i| p[i].dist(p[(i + 1) % p.len()])).sum()
}

/// The bottom section is the squircle, the top the circle: each an
/// inscribed polygon of the exact curve, so its area is below the exact one
/// by at most the perimeter times the chords' sagitta bound (0.1 × the
/// tolerance, `levels::plan::CHORD_FRACTION`).
#[test]
fn the_end_sections_have_the_exact_areas() {
    assert!((squircle_area_by_quadrature() - SQUIRCLE_AREA).abs() < 1e-9);
    let j = job(&tube_job(VASE, "")).unwrap();
    assert_eq!(j.operation.depth, 15.0);
    let s = sections(&j);
    assert_eq!(s.z_range(), (-15.0, 0.0));
    for (z, exact) in [(-15.0, SQUIRCLE_AREA), (0.0, 36.0 * PI)] {
        let sec = s.section(z);
        assert_eq!(sec.len(), 1, "z {z}: one ring");
        let area = net_area(&sec);
        let bound = perimeter(&sec[0]) * 0.1 * 0.01;
        assert!(
            area <= exact + 1e-9 && exact - area <= bound,
            "z {z}: {area} against {exact} (bound {bound})"
        );
    }
    assert!(s.level_value(-15.0).abs() < 1e-12 && (s.level_value(0.0) - 1.0).abs() < 1e-12);
}

/// The job's sections equal those of a tube built here from the same curves
/// written out independently (the squircle in polar form), at every height
/// tried, vertex by vertex; and moved by `shape.origin`.
#[test]
fn the_jobs_sections_are_the_tubes_own() {
    let k = 128;
    let ring = |f: &dyn Fn(f64) -> [f64; 3]| -> Vec<[f64; 3]> {
        (0..k).map(|i| f(TAU * i as f64 / k as f64)).collect()
    };
    let curves = BoundaryCurves {
        x0: ring(&|v| {
            let r = 10.0 / (v.cos().powi(4) + v.sin().powi(4)).powf(0.25);
            [5.0 + r * v.cos(), -7.0 + r * v.sin(), 0.0]
        }),
        x1: ring(&|v| [5.0 + 6.0 * v.cos(), -7.0 + 6.0 * v.sin(), 15.0]),
        xu0: ring(&|v| [-6.0 * v.cos(), -6.0 * v.sin(), 15.0]),
        xu1: ring(&|v| [-3.0 * v.cos(), -3.0 * v.sin(), 15.0]),
    };
    let shape = format!("{VASE}flare = [-6.0, -3.0]\norigin = [5.0, -7.0]\n");
    let j = job(&tube_job(&shape, "")).unwrap();
    let s = sections(&j);
    let ShapeSource::PdeTube(spec) = &j.shape else {
        panic!("a tube")
    };
    let p = spec.points(&spec.surface().unwrap());
    let own = PdeTube::new(&curves, 1.0, 8, TubeKind::Boss, Vec::new(), (p, 0.01)).unwrap();
    for z in [-15.0, -11.3, -7.5, -2.2, 0.0] {
        let (a, b) = (s.section(z), own.section(z));
        assert_eq!(a.len(), b.len());
        for (pa, pb) in a[0].iter().zip(&b[0]) {
            assert!(pa.dist(*pb) < 1e-9, "z {z}: {pa:?} {pb:?}");
        }
        assert!(a[0].len() == p && net_area(&a) > 0.0);
    }
}

/// `operation.kind = "cavity"` is the mould: the boss upside down, its
/// sections the boss's at the mirrored height, as holes.
#[test]
fn the_mould_is_the_boss_upside_down() {
    let boss = sections(&job(&tube_job(VASE, "")).unwrap());
    let mould = sections(&job(&tube_job(VASE, "kind = \"cavity\"\n")).unwrap());
    assert_eq!(mould.z_range(), (-15.0, 0.0));
    for z in [-15.0, -12.0, -6.5, -1.0, 0.0] {
        let (b, m) = (boss.section(z), mould.section(-15.0 - z));
        let (ab, am) = (net_area(&b), net_area(&m));
        assert!(ab > 0.0 && (ab + am).abs() < 1e-6 * ab, "z {z}: {ab} {am}");
        for q in &m[0] {
            let d = b[0]
                .iter()
                .map(|p| p.dist(*q))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d < 1e-9,
                "z {z}: {q:?} is not a vertex of the boss's section"
            );
        }
    }
    // The rim is the squircle at the stock top.
    assert!((net_area(&mould.section(0.0)) + SQUIRCLE_AREA).abs() < 0.1);
}

/// Every refusal names its key; the overhang and the turning spine name
/// the z.
#[test]
fn errors_name_their_keys() {
    let err = |shape: &str, extra: &str| job(&tube_job(shape, extra)).unwrap_err();
    let starts = |e: String, key: &str| assert!(e.starts_with(key), "{key}: {e}");
    starts(
        err("top_size = [12.0, 12.0]\nheight = 15.0", ""),
        "shape.bottom_size",
    );
    starts(
        err("bottom_size = [20.0, 20.0]\nheight = 15.0", ""),
        "shape.top_size",
    );
    starts(
        err("bottom_size = [20.0, 20.0]\ntop_size = [12.0, 12.0]", ""),
        "shape.height",
    );
    let vase = |from: &str, to: &str| VASE.replace(from, to);
    starts(
        err(&vase("bottom_exponent = 4.0", "bottom_exponent = 0.5"), ""),
        "shape.bottom_exponent",
    );
    starts(
        err(
            &vase("bottom_size = [20.0, 20.0]", "bottom_size = [0.0, 3.0]"),
            "",
        ),
        "shape.bottom_size",
    );
    starts(err(&format!("{VASE}a = 0.0"), ""), "shape.a");
    starts(err(&format!("{VASE}modes = 65"), ""), "shape.modes");
    let e = err(&format!("{VASE}modes = 20\nsamples = 32"), "");
    assert!(e.starts_with("shape.samples") && e.contains("41"), "{e}");
    starts(err(&format!("{VASE}flare = [1e9, 0.0]"), ""), "shape.flare");
    starts(err(&format!("{VASE}degree = 3"), ""), "shape.degree");
    starts(err(&format!("{VASE}text = \"I\""), ""), "shape.text");
    starts(err(VASE, "depth = 3.0\n"), "operation.depth");
    starts(err(VASE, "kind = \"profile\"\n"), "operation.kind");
    starts(
        job(&format!(
            "{}[profile]\nkind = \"linear\"\n",
            tube_job(VASE, "")
        ))
        .unwrap_err(),
        "profile",
    );
    starts(
        job(&format!(
            "{}[finish]\nshape = \"flat\"\ndiameter = 3.0\n",
            tube_job(VASE, "")
        ))
        .unwrap_err(),
        "finish.shape",
    );
    assert!(job(&format!("{}[finish]\ndiameter = 3.0\n", tube_job(VASE, ""))).is_ok());
    // Tube keys without the kind.
    let e = job("[shape]\ntext = \"I\"\nmodes = 3\n[tool]\ndiameter = 3\n[operation]\ndepth = 1\n")
        .unwrap_err();
    assert!(e.starts_with("shape.modes only applies"), "{e}");
    // A boss wider at the top overhangs, named at the first pair of heights
    // (201 evenly spaced, 0.075 mm apart) where its radius grows by more
    // than the tolerance: checked here on the axisymmetric surface itself
    // (circles at both ends, z = 15u exactly: rise = height, no flare).
    let wide_top = "bottom_size = [12.0, 12.0]\ntop_size = [20.0, 20.0]\nheight = 15.0\n";
    let e = err(wide_top, "");
    assert!(
        e.starts_with("shape.top_size makes the part overhang at z = "),
        "{e}"
    );
    let named = |e: &str| -> (f64, f64) {
        let rest = e.split("(between z = ").nth(1).expect("the heights");
        let mut it = rest.split([' ', ')']);
        let lower: f64 = it.next().unwrap().parse().unwrap();
        let upper: f64 = it.nth(1).unwrap().parse().unwrap();
        (lower, upper)
    };
    let (lower, upper) = named(&e);
    assert!((upper - lower - 0.075).abs() < 1e-3 && lower >= -15.0 && upper <= 0.0);
    let surface = {
        use pfcam::sources::pde_tube::spec::{TubeEnd, TubeSpec};
        let end = |d: f64| TubeEnd {
            size: [d, d],
            exponent: 2.0,
            flare: 0.0,
            rise: 15.0,
        };
        let spec = TubeSpec {
            bottom: end(12.0),
            top: end(20.0),
            height: 15.0,
            a: 1.0,
            modes: 8,
            samples: 128,
            origin: Vec2::ZERO,
            kind: TubeKind::Boss,
            tolerance: 0.01,
            trims: Vec::new(),
        };
        spec.surface().unwrap()
    };
    let radius = |z: f64| {
        let p = surface.point((z + 15.0) / 15.0, 0.3);
        p[0].hypot(p[1])
    };
    assert!(radius(upper) - radius(lower) > 0.01, "{e}");
    assert!(radius(lower) - radius(lower - 0.075) <= 0.01, "{e}");
    // The vase's mould (the vase upside down: its pocket widens from the
    // floor to the rim) is accepted; the wide-topped tube's mould, whose
    // pocket would narrow upward, is refused likewise.
    assert!(job(&tube_job(VASE, "kind = \"cavity\"\n")).is_ok());
    let e = err(wide_top, "kind = \"cavity\"\n");
    assert!(
        e.starts_with("shape.top_size makes the part overhang"),
        "{e}"
    );
    // A flare that bulges the wall out: named by shape.flare, with the z
    // in the lower half, where the flare pushes the wall out.
    let e = err(&format!("{VASE}flare = [30.0, 0.0]"), "");
    assert!(
        e.starts_with("shape.flare makes the part overhang at z = "),
        "{e}"
    );
    let (lower, _) = named(&e);
    assert!((-15.0..-7.5).contains(&lower), "{e}");
    // A spine whose z turns back: rise against the height.
    let e = err(&format!("{VASE}rise = [15.0, -40.0]"), "");
    assert!(
        e.starts_with("shape.rise makes the tube's spine turn back in z at z = "),
        "{e}"
    );
}

/// The part's closed mesh (`pfcam surface`'s): watertight and oriented, the
/// stock rectangle the run's, the boss's volume the floor slab plus the
/// tube's (Simpson over its sections), the mould's the block less the tube.
#[test]
fn the_part_mesh_is_closed_with_the_tubes_volume() {
    use pfcam::surface::{job_part_surface, SurfaceOptions, BASE_THICKNESS};
    let opts = SurfaceOptions { resolution: 0.4 };
    let boss = job(&tube_job(VASE, "")).unwrap();
    let s = sections(&boss);
    let tube: f64 = (0..60)
        .map(|k| {
            let (a, b) = (-15.0 + 0.25 * k as f64, -15.0 + 0.25 * (k + 1) as f64);
            let area = |z: f64| net_area(&s.section(z));
            0.25 / 6.0 * (area(a) + 4.0 * area(0.5 * (a + b)) + area(b))
        })
        .sum();
    // The stock: the squircle's box (±10 mm) and the default 5 mm margin.
    let rect = 30.0 * 30.0;
    for (j, want) in [
        (boss, rect * BASE_THICKNESS + tube),
        (
            job(&tube_job(VASE, "kind = \"cavity\"\n")).unwrap(),
            rect * (15.0 + BASE_THICKNESS) - tube,
        ),
    ] {
        let m = job_part_surface(&j, &opts, &mut |_| {}).unwrap();
        m.mesh.check().unwrap();
        let (lo, hi) = m.mesh.bbox().unwrap();
        for (got, exact) in [(lo[0], -15.0), (lo[1], -15.0), (hi[0], 15.0), (hi[1], 15.0)] {
            assert!((got - exact).abs() < 1e-9, "{got} against {exact}");
        }
        assert_eq!((lo[2], hi[2]), (-15.0 - BASE_THICKNESS, 0.0));
        let v = m.mesh.volume();
        let kind = j.operation.kind;
        assert!(
            (v - want).abs() < 2e-3 * tube,
            "{kind:?}: {v} against {want}"
        );
    }
}

/// jobs/pde-vase.toml's golden samples, roughed then finished along the
/// sections, simulated by the binary against the tube's part: no rapid
/// into material and no straight plunge in either program, no cell cut into
/// the part by more than the tolerance, and the material the ball can reach
/// left within finish.scallop + 0.01 mm.
#[test]
fn the_shipped_vase_simulates_clean() {
    let v = crate::common::simulate_report(
        &[
            "gcode-samples/pde-vase.rough.nc",
            "gcode-samples/pde-vase.finish.nc",
        ],
        "jobs/pde-vase.toml",
        crate::common::root(),
    );
    let part = &v["part"];
    assert_eq!(part["model"], "PDE tube");
    let gouge = part["max_gouge"]["value"].as_f64().unwrap();
    assert!((0.0..=0.01).contains(&gouge), "max gouge {gouge}");
    assert_eq!(part["gouged_cells"], 0, "{part}");
    let left = part["max_left_reachable"]["value"].as_f64().unwrap();
    assert!((0.0..=0.01 + 0.01).contains(&left), "material left {left}");
    let programs = v["programs"].as_array().unwrap();
    assert_eq!(programs.len(), 2);
    for p in programs {
        let r = &p["report"];
        assert_eq!(r["rapids_into_material"], 0, "{r}");
        assert_eq!(r["straight_plunges"], 0, "{r}");
    }
}

/// `pfcam surface` on the shipped vase and on its mould (the same job with
/// `operation.kind = "cavity"`): each STL, read back from its bytes and
/// welded as a viewer would, is watertight and oriented with no zero-area
/// triangle (the check the other sources' STLs pass), spans the stock and
/// the depth, and the two volumes add up to the whole block (30 × 30 mm,
/// 15 mm and the 2 mm base): the mould is the boss's complement.
#[test]
fn pfcam_surface_writes_the_vase_and_its_mould_watertight() {
    use crate::common::{pfcam as bin, root, scratch, text};
    use pfcam::surface::{read_stl, weld, BASE_THICKNESS};
    let dir = scratch("pde_job", "surface");
    let vase = std::fs::read_to_string(root().join("jobs/pde-vase.toml")).unwrap();
    let mould = vase
        .replace("name = \"pde-vase\"", "name = \"pde-vase-mould\"")
        .replace("kind = \"boss\"", "kind = \"cavity\"");
    assert_ne!(mould, vase);
    std::fs::write(dir.join("mould.toml"), mould).unwrap();
    let job = root().join("jobs/pde-vase.toml");
    let mut volumes = Vec::new();
    for (job, stl) in [
        (job.to_str().unwrap(), "vase.stl"),
        ("mould.toml", "mould.stl"),
    ] {
        let out = bin(&["surface", job, "-o", stl, "-q"], &dir);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let bytes = std::fs::read(dir.join(stl)).unwrap();
        let (_, tris) = read_stl(&bytes).unwrap();
        let mesh = weld(&tris);
        mesh.check().unwrap_or_else(|e| panic!("{stl}: {e}"));
        let (lo, hi) = mesh.bbox().unwrap();
        for (got, want) in [(lo[0], -15.0), (hi[1], 15.0), (lo[2], -17.0), (hi[2], 0.0)] {
            assert!((got - want).abs() < 1e-5, "{stl}: {got} against {want}");
        }
        volumes.push(mesh.volume());
    }
    let block = 30.0 * 30.0 * (15.0 + BASE_THICKNESS);
    let tube = volumes[0] - 30.0 * 30.0 * BASE_THICKNESS;
    assert!(tube > 3000.0 && tube < 15.0 * 400.0, "{volumes:?}");
    assert!(
        (volumes[0] + volumes[1] - (block + 30.0 * 30.0 * BASE_THICKNESS)).abs() < 1e-3,
        "{volumes:?}"
    );
}

/// The tube and the polyharmonic relief share `shape.a` (the PDE's
/// parameter, the T2A ball radius) and refuse each other's other keys.
#[test]
fn a_tube_and_a_relief_refuse_each_others_keys() {
    let with_a = format!("{VASE}a = 2.0\n");
    assert!(job(&tube_job(&with_a, "")).is_ok());
    for (line, key) in [
        ("kernel = \"T2A\"", "shape.kernel"),
        ("points = [[0.0, 0.0, 1.0]]", "shape.points"),
        ("base = 0.0", "shape.base"),
        ("solid = \"closed\"", "shape.solid"),
        ("degree = 3", "shape.degree"),
    ] {
        let e = job(&tube_job(&format!("{VASE}{line}\n"), "")).unwrap_err();
        assert!(e.starts_with(key), "{key}: {e}");
    }
    let relief = std::fs::read_to_string(crate::common::root().join("jobs/polyharmonic-face.toml"))
        .expect("read the relief job");
    for (line, key) in [
        ("modes = 8", "shape.modes"),
        ("top_size = [1.0, 1.0]", "shape.top_size"),
    ] {
        let text = relief.replacen("[shape]\n", &format!("[shape]\n{line}\n"), 1);
        let e = parse_job(&text, "face", &crate::common::root().join("jobs"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(key), "{key}: {e}");
    }
}
