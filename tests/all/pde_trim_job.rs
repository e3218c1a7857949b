//! A trimmed PDE tube as a job (`[[shape.trim]]`, docs/method.md §16.3 "As
//! a job"): jobs/pde-trimmed.toml's sections against the untrimmed vase's
//! less the sector computed independently from the surface; the part's
//! mesh closed, its volume the vase's less the slot's; the keys' refusals;
//! the shipped samples simulated clean and `pfcam surface`'s STL watertight.

use pfcam::geometry::ShapeSource;
use pfcam::job::{parse_job, Job};
use pfcam::levels::sections::{net_area, Sections};
use pfcam::pipeline;
use std::path::Path;

fn shipped() -> String {
    std::fs::read_to_string(crate::common::root().join("jobs/pde-trimmed.toml")).unwrap()
}

fn job(body: &str) -> Result<Job, String> {
    parse_job(body, "trim", Path::new(".")).map_err(|e| e.to_string())
}

/// The shipped job without its trim: jobs/pde-vase.toml's vase.
fn untrimmed() -> String {
    let text = shipped();
    let from = text.find("[[shape.trim]]").unwrap();
    let to = from + text[from..].find("[tool]").unwrap();
    format!("{}{}", &text[..from], &text[to..])
}

fn sections(j: &Job) -> Box<dyn Sections> {
    pipeline::job_sections(j, &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// The area (mm²) between the spine point and the surface's curve X(u, v)
/// for v from −45° to 45°, by the shoelace of 20000 points of X itself (not
/// the section's polygon) and the spine point.
fn sector_area(j: &Job, u: f64) -> f64 {
    let ShapeSource::PdeTube(spec) = &j.shape else {
        panic!("a tube")
    };
    let s = spec.surface().unwrap();
    let c = s.spine().point(u);
    let n = 20_000;
    let (a, b) = (-45f64.to_radians(), 45f64.to_radians());
    let p = |i: usize| {
        let q = s.point(u, a + (b - a) * i as f64 / n as f64);
        (q[0] - c[0], q[1] - c[1])
    };
    (0..n)
        .map(|i| {
            let (x0, y0) = p(i);
            let (x1, y1) = p(i + 1);
            0.5 * (x0 * y1 - x1 * y0)
        })
        .sum()
}

/// Above the slot's floor the section is the vase's less the sector; at the
/// floor's own z the slot is cut (a level there cuts the floor), just
/// under it the whole curve.
#[test]
fn the_sections_are_the_vases_less_the_sector() {
    let (trimmed, plain) = (job(&shipped()).unwrap(), job(&untrimmed()).unwrap());
    let (st, sp) = (sections(&trimmed), sections(&plain));
    for z in [-6.0, -4.5, -2.0, -0.25, 0.0] {
        let u = st.level_value(z);
        let (kept, whole) = (net_area(&st.section(z)), net_area(&sp.section(z)));
        let sector = sector_area(&plain, u);
        assert!(
            sector > 0.2 * whole && sector < 0.3 * whole,
            "{sector} of {whole}"
        );
        let err = kept - (whole - sector);
        // Both polygons' chords are within 0.001 mm of the curve.
        assert!(
            err.abs() < 2e-4 * whole,
            "z {z}: {kept} against {whole} − {sector} ({err:+.2e})"
        );
        assert_eq!(st.section(z).len(), 1, "one pie piece at z {z}");
    }
    for z in [-6.0 - 1e-6, -10.0, -15.0] {
        assert_eq!(st.section(z), sp.section(z), "untrimmed at z {z}");
    }
}

/// The part's mesh (`pfcam surface`'s, 0.4 mm) is closed, and its volume
/// is the vase's less the slot: the sector areas integrated over the slot's
/// 6 mm (Simpson, 24 slices).
#[test]
fn the_part_mesh_is_closed_and_the_slot_is_out_of_it() {
    use pfcam::surface::{job_part_surface, SurfaceOptions};
    let opts = SurfaceOptions { resolution: 0.4 };
    let (trimmed, plain) = (job(&shipped()).unwrap(), job(&untrimmed()).unwrap());
    let st = sections(&trimmed);
    let sector = |z: f64| sector_area(&plain, st.level_value(z));
    let slot: f64 = (0..24)
        .map(|k| {
            let (a, b) = (-6.0 + 0.25 * k as f64, -6.0 + 0.25 * (k + 1) as f64);
            0.25 / 6.0 * (sector(a) + 4.0 * sector(0.5 * (a + b)) + sector(b))
        })
        .sum();
    let mut v = Vec::new();
    for j in [&trimmed, &plain] {
        let m = job_part_surface(j, &opts, &mut |_| {}).unwrap();
        m.mesh.check().unwrap();
        v.push(m.mesh.volume());
    }
    assert!(slot > 200.0, "{slot}");
    let err = (v[1] - v[0]) - slot;
    assert!(
        err.abs() < 2e-3 * slot,
        "{v:?}: removed {} against {slot}",
        v[1] - v[0]
    );
}

/// `[[shape.trim]]`'s refusals, each naming its key.
#[test]
fn trim_errors_name_their_keys() {
    let with = |trim: &str| {
        shipped().replace(
            "angles = [-45.0, 45.0]       # degrees, counter-clockwise from +x: a quarter facing +x\nz = [-6.0, 0.0]              # mm: from the slot's floor up to the rim (the part's top)",
            trim,
        )
    };
    assert_ne!(with("x"), shipped());
    let cases: [(String, &str, &str); 9] = [
        (with("angles = [-45.0, 45.0]\nz = [-8.0, -3.0]"), "shape.trim[1].z", "window"),
        (with("angles = [-45.0, 45.0]\nz = [-15.0, 0.0]"), "shape.trim[1].z", "foot"),
        (with("angles = [-45.0, 45.0]\nz = [-6.0, -6.0]"), "shape.trim[1].z", "bottom below top"),
        (with("angles = [0.0, 200.0]\nz = [-6.0, 0.0]"), "shape.trim[1].angles", "less than 180"),
        (with("angles = [45.0, -45.0]\nz = [-6.0, 0.0]"), "shape.trim[1].angles", "above the first"),
        (with("angles = [-400.0, 0.0]\nz = [-6.0, 0.0]"), "shape.trim[1].angles", "[-360, 360]"),
        (with("z = [-6.0, 0.0]"), "shape.trim[1].angles", "required"),
        (
            with("angles = [-45.0, 45.0]\nz = [-6.0, 0.0]\n\n[[shape.trim]]\nangles = [90.0, 120.0]\nz = [-3.0, 0.0]"),
            "shape.trim",
            "at most 1",
        ),
        (
            with("angles = [-45.0, 45.0]\nz = [-6.0, 0.0]").replace("kind = \"boss\"", "kind = \"cavity\""),
            "shape.trim",
            "boss only",
        ),
    ];
    for (text, key, what) in cases {
        let e = job(&text).unwrap_err();
        assert!(e.starts_with(key), "{key}: {e}");
        assert!(e.contains(what), "{key} ({what}): {e}");
    }
    let e = job(&with("angles = [-45.0, 45.0]\nz = [-8.0, -3.0]")).unwrap_err();
    assert!(e.contains("overhangs the opening at z = -3"), "{e}");
    let e = job(&with("angles = [-45.0, 45.0]\nwidth = 2.0")).unwrap_err();
    assert!(e.contains("shape.trim[1].width"), "{e}");
    let text = "[shape]\ntext = \"A\"\n\n[[shape.trim]]\nangles = [0.0, 10.0]\nz = [-1.0, 0.0]\n\n[tool]\ndiameter = 3.175\n";
    let e = job(text).unwrap_err();
    assert!(e.starts_with("shape.trim") && e.contains("pde-tube"), "{e}");
}

/// The shipped samples, roughed then finished round the slot, simulated by
/// the binary against the trimmed part: no rapid into material and no
/// straight plunge, no cell cut into the part by more than the tolerance,
/// the material the ball can reach left within finish.scallop + 0.01 mm.
#[test]
fn the_shipped_trimmed_vase_simulates_clean() {
    let v = crate::common::simulate_report(
        &[
            "gcode-samples/pde-trimmed.rough.nc",
            "gcode-samples/pde-trimmed.finish.nc",
        ],
        "jobs/pde-trimmed.toml",
        crate::common::root(),
    );
    let part = &v["part"];
    let gouge = part["max_gouge"]["value"].as_f64().unwrap();
    assert!((0.0..=0.01).contains(&gouge), "max gouge {gouge}");
    assert_eq!(part["gouged_cells"], 0, "{part}");
    let left = part["max_left_reachable"]["value"].as_f64().unwrap();
    assert!((0.0..=0.01 + 0.01).contains(&left), "material left {left}");
    for p in v["programs"].as_array().unwrap() {
        let r = &p["report"];
        assert_eq!(r["rapids_into_material"], 0, "{r}");
        assert_eq!(r["straight_plunges"], 0, "{r}");
    }
}

/// `pfcam surface` writes the trimmed vase watertight: read back from the
/// STL's bytes and welded, closed and oriented, spanning the stock.
#[test]
fn pfcam_surface_writes_the_trimmed_vase_watertight() {
    use crate::common::{pfcam as bin, root, scratch, text};
    use pfcam::surface::{read_stl, weld};
    let dir = scratch("pde_trim_job", "surface");
    let job = root().join("jobs/pde-trimmed.toml");
    let out = bin(
        &["surface", job.to_str().unwrap(), "-o", "t.stl", "-q"],
        &dir,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (_, tris) = read_stl(&std::fs::read(dir.join("t.stl")).unwrap()).unwrap();
    let mesh = weld(&tris);
    mesh.check().unwrap();
    let (lo, hi) = mesh.bbox().unwrap();
    for (got, want) in [(lo[0], -15.0), (hi[1], 15.0), (lo[2], -17.0), (hi[2], 0.0)] {
        assert!((got - want).abs() < 1e-5, "{got} against {want}");
    }
}
