//! docs/method.md §16 (Ugail 002/004: four-curve conditions, trimming, the tube
//! as a part): its measured figures, recomputed and held to the doc as written
//! (the commands are `cargo run --release --example pde_figures`).

use crate::doc_figures;
use pfcam::levels::sections::{net_area, Sections};
use pfcam::sources::pde::{four_curve_conditioning, BoundaryCurves};
use pfcam::sources::pde_trim::{resample_closed, TrimCurves, TrimMap};
use pfcam::sources::pde_tube::{PdeTube, TubeError, TubeKind};
use std::f64::consts::{PI, TAU};

const DOC: &str = "docs/method.md";

/// §16 of the doc, up to the next section.
fn section16() -> String {
    let doc = doc_figures::read(DOC);
    let s = doc_figures::after(&doc, DOC, "## 16. Four-curve conditions");
    s.split("\n## ").next().unwrap_or_default().to_string()
}

/// A rounding-level figure (e.g. 2.85e-14): within a factor 4 of a fresh one,
/// which other compilers and machines may round differently.
fn assert_rounding(what: &str, figure: &str, value: f64) {
    let quoted: f64 = figure
        .parse()
        .unwrap_or_else(|_| panic!("{what}: {figure}"));
    assert!(
        value <= 4.0 * quoted && value >= quoted / 4.0,
        "{what}: the doc says {figure}, now {value:e}"
    );
}

#[test]
fn the_four_curve_conditioning_table_is_measured() {
    let sec = section16();
    let lambdas = [0.0, 1.0, 5.0, 10.0, 20.0, 30.0, 40.0, 60.0, 80.0];
    for (label, s, t, cond_row) in [
        ("(0.3, 0.7) gain", 0.3, 0.7, true),
        ("(⅓, ⅔) gain", 1.0 / 3.0, 2.0 / 3.0, false),
        ("(0.2, 0.45) gain", 0.2, 0.45, true),
    ] {
        let gains = doc_figures::table_row(&sec, DOC, label);
        let after = doc_figures::after(&sec, DOC, label);
        let conds = doc_figures::table_row(after, DOC, "cond");
        for (i, &l) in lambdas.iter().enumerate() {
            let r = four_curve_conditioning(0, l, s, t);
            let what = format!("{DOC} §16.1, {label} at λ = {l}");
            doc_figures::assert_figure(&what, gains[i + 1], r.gain);
            if cond_row {
                doc_figures::assert_figure(&format!("{what}, cond"), conds[i + 1], r.cond);
            }
        }
    }
}

#[test]
fn the_trim_map_figures_are_measured() {
    let sec = section16();
    let k = 128;
    let square = [
        [1.0, PI],
        [1.0, PI + 0.5],
        [0.0, PI + 0.5],
        [0.0, PI - 0.5],
        [1.0, PI - 0.5],
    ];
    let circle = |e: f64| [0.5 + 0.2 * e.cos(), PI + 0.2 * e.sin()];
    let kidney = |e: f64| {
        let r = 0.2 * (1.0 + 0.35 * (2.0 * e).cos() - 0.1 * (3.0 * e).sin());
        [0.5 + r * e.cos(), PI + r * e.sin()]
    };
    type Curve<'a> = &'a dyn Fn(f64) -> [f64; 2];
    let shapes: [(&str, Curve); 2] = [("circle", &circle), ("kidney", &kidney)];
    for (name, f) in shapes {
        let c = TrimCurves {
            trim: (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect(),
            border: resample_closed(&square, k),
        };
        let m = TrimMap::solve(&c, 8).unwrap();
        let d = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
        let met = (0..k)
            .map(|j| {
                let eta = TAU * j as f64 / k as f64;
                d(m.map(0.0, eta), c.trim[j]).max(d(m.map(1.0, eta), c.border[j]))
            })
            .fold(0.0, f64::max);
        let (det, _, _) = m.min_jacobian(400, 4096);
        let row = doc_figures::table_row(&sec, DOC, name);
        assert_rounding(&format!("{DOC} §16.2, {name}, curves met"), row[1], met);
        doc_figures::assert_figure(&format!("{DOC} §16.2, {name}, min J"), row[2], det);
    }
}

fn ring(k: usize, f: impl Fn(f64) -> [f64; 3]) -> Vec<[f64; 3]> {
    (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
}

#[test]
fn the_vase_figures_are_measured() {
    let sec = section16();
    let k = 128;
    let squircle = |v: f64| {
        let (s, c) = v.sin_cos();
        let r = 10.0 / (c.powi(4) + s.powi(4)).powf(0.25);
        [r * c, r * s, 0.0]
    };
    let curves = BoundaryCurves {
        x0: ring(k, squircle),
        x1: ring(k, |v| [6.0 * v.cos(), 6.0 * v.sin(), 15.0]),
        xu0: ring(k, |_| [0.0, 0.0, 15.0]),
        xu1: ring(k, |_| [0.0, 0.0, 15.0]),
    };
    let boss = PdeTube::new(&curves, 1.0, 8, TubeKind::Boss, vec![], (512, 0.01)).unwrap();
    for (first, z) in [
        ("−15", -15.0),
        ("−11.25", -11.25),
        ("−7.5", -7.5),
        ("−3.75", -3.75),
        ("0", 0.0),
    ] {
        let row = doc_figures::table_row(&sec, DOC, first);
        let what = format!("{DOC} §16.3, z = {z}");
        doc_figures::assert_figure(&what, row[1], boss.level_value(z));
        doc_figures::assert_figure(&what, row[2], net_area(&boss.section(z)));
    }
    let s = boss.surface();
    let mut ez: f64 = 0.0;
    for i in 0..=100 {
        for j in 0..256 {
            let (u, v) = (i as f64 / 100.0, TAU * j as f64 / 256.0);
            ez = ez.max((s.point(u, v)[2] - s.spine().point(u)[2]).abs());
        }
    }
    let stated = doc_figures::number_after(&sec, DOC, "|X_z − A₀z| =");
    assert_rounding(&format!("{DOC} §16.3, X_z − A₀z"), &stated, ez);
    let window = vec![vec![[0.6, 1.0], [1.2, 1.0], [1.2, 2.0], [0.6, 2.0]]];
    match PdeTube::new(&curves, 1.0, 8, TubeKind::Boss, window, (512, 1e-9)) {
        Err(TubeError::Overhang { by, .. }) => {
            let stated = doc_figures::number_after(&sec, DOC, "z −5.925 to −5.85, by");
            doc_figures::assert_figure(&format!("{DOC} §16.3, window"), &stated, by);
        }
        other => panic!("the window at tol 1e-9: {:?}", other.map(|_| ())),
    }
}
