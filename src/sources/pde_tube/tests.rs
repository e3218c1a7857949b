use super::*;
use crate::levels::sections::net_area;
use crate::num::testing::uniforms;

/// The nesting tolerance of the tests (mm): a job's `tol`.
const TOL: f64 = 1e-3;

fn ring(k: usize, f: impl Fn(f64) -> [f64; 3]) -> Vec<[f64; 3]> {
    (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
}

fn squircle(v: f64) -> [f64; 3] {
    let (s, c) = v.sin_cos();
    let r = 10.0 / (c.powi(4) + s.powi(4)).powf(0.25);
    [r * c, r * s, 0.0]
}

/// The vase: a squircle (|x|⁴ + |y|⁴ = 10⁴) at z = 0 to a circle of
/// radius 6 at z = 15, Xᵤ = (0, 0, 15) at both ends; `flip` swaps the ends.
fn vase(k: usize, flip: bool) -> BoundaryCurves {
    let circle = ring(k, |v| [6.0 * v.cos(), 6.0 * v.sin(), 15.0]);
    let mut sq = ring(k, squircle);
    let mut top = circle;
    if flip {
        sq.iter_mut().for_each(|p| p[2] = 15.0);
        top.iter_mut().for_each(|p| p[2] = 0.0);
        std::mem::swap(&mut sq, &mut top);
    }
    BoundaryCurves {
        x0: sq,
        x1: top,
        xu0: ring(k, |_| [0.0, 0.0, 15.0]),
        xu1: ring(k, |_| [0.0, 0.0, 15.0]),
    }
}

/// Circles of radius ρ = 5 at z = 0 and 20, Xᵤ = (±s cos v, ±s sin v, 20).
fn cylinder(k: usize, s: f64) -> BoundaryCurves {
    BoundaryCurves {
        x0: ring(k, |v| [5.0 * v.cos(), 5.0 * v.sin(), 0.0]),
        x1: ring(k, |v| [5.0 * v.cos(), 5.0 * v.sin(), 20.0]),
        xu0: ring(k, |v| [s * v.cos(), s * v.sin(), 20.0]),
        xu1: ring(k, |v| [-s * v.cos(), -s * v.sin(), 20.0]),
    }
}

/// The closed-form radius at u = ½ (docs/method.md §15).
fn waist(rho: f64, s: f64, a: f64) -> f64 {
    let h = 0.5;
    let (sh, ch) = ((a * h).sinh(), (a * h).cosh());
    (rho * (sh + a * h * ch) + s * h * sh) / (sh * ch + a * h)
}

/// A tube without the checks of `new` (the sections of a part that overhangs).
fn unchecked(c: &BoundaryCurves, trims: Vec<Vec<[f64; 2]>>, points: usize) -> PdeTube {
    let surface = PdeSurface::solve(c, 1.0, 4).unwrap();
    let sp = surface.spine();
    PdeTube {
        z_ends: (sp.p1[2], sp.p2[2]),
        surface,
        kind: TubeKind::Boss,
        trims,
        points,
    }
}

fn rect(u0: f64, u1: f64, v0: f64, v1: f64) -> Vec<[f64; 2]> {
    vec![[u0, v0], [u1, v0], [u1, v1], [u0, v1]]
}

#[test]
fn horizontal_end_data_give_x_z_equal_to_the_spine() {
    let t = PdeTube::new(&vase(64, false), 1.0, 6, TubeKind::Boss, vec![], (256, TOL)).unwrap();
    let s = t.surface();
    for p in uniforms(1, 400).chunks(2) {
        let (u, v) = (p[0], TAU * p[1]);
        let (x, a) = (s.point(u, v)[2], s.spine().point(u)[2]);
        assert!((x - a).abs() < 1e-12, "u = {u}, v = {v}: {x} vs {a}");
        assert!(s.du(u, v)[2] - s.spine().derivative(u)[2] < 1e-12);
    }
    assert_eq!(t.z_range(), (-15.0, 0.0));
    for z in [-15.0, -9.3, -0.1, 0.0] {
        assert!((t.z_of(t.u_of(z)) - z).abs() < 1e-12, "{z}");
        assert_eq!(t.level_value(z), t.u_of(z));
    }
    assert!(t.level_field(-3.0).is_none());
}

/// Crossing-number inside test (independent of the module's).
fn inside(region: &[Vec<Vec2>], q: Vec2) -> bool {
    let mut c = false;
    for p in region {
        for i in 0..p.len() {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                c = !c;
            }
        }
    }
    c
}

#[test]
fn the_vase_nests_as_a_boss_and_upside_down_as_a_mould() {
    let boss = PdeTube::new(
        &vase(128, false),
        1.0,
        8,
        TubeKind::Boss,
        vec![],
        (256, TOL),
    )
    .unwrap();
    // 40 random pairs: every vertex of the higher section inside the lower one
    // (shrunk by 1e-9 mm: a vertex on both is allowed).
    for p in uniforms(5, 80).chunks(2) {
        let (lo, hi) = (-15.0 * p[0].max(p[1]), -15.0 * p[0].min(p[1]));
        let (a, b) = (boss.section(lo), boss.section(hi));
        assert!(net_area(&a) >= net_area(&b) && net_area(&b) > 0.0);
        for q in &b[0] {
            let shrunk = *q * (1.0 - 1e-9);
            assert!(inside(&a, shrunk), "z {hi} at {q:?} outside z {lo}");
        }
    }
    let mould = PdeTube::new(
        &vase(128, true),
        1.0,
        8,
        TubeKind::Mould,
        vec![],
        (256, TOL),
    )
    .unwrap();
    let (top, bottom) = (mould.section(0.0), mould.section(-15.0));
    assert!(net_area(&top) < net_area(&bottom) && net_area(&bottom) < 0.0);
    // The vase itself as a mould (pocket narrowing upward) overhangs.
    let e = PdeTube::new(
        &vase(128, false),
        1.0,
        8,
        TubeKind::Mould,
        vec![],
        (256, TOL),
    )
    .unwrap_err();
    assert!(matches!(e, TubeError::Overhang { .. }), "{e}");
}

#[test]
fn an_overhang_is_refused_naming_a_z_inside_it() {
    // s = 6 bulges: the radius grows from u = 0 to ½, z = 20u, so the boss
    // overhangs for z from −20 to −10 (relative to its top).
    let e = PdeTube::new(
        &cylinder(32, 6.0),
        1.0,
        4,
        TubeKind::Boss,
        vec![],
        (128, TOL),
    )
    .unwrap_err();
    match &e {
        TubeError::Overhang {
            z, lower, upper, ..
        } => {
            assert!(
                *lower >= -20.0 && *upper < -10.0 && lower < z && z < upper,
                "{e}"
            );
            assert!(e.to_string().contains(&format!("{z:.4}")), "{e}");
        }
        other => panic!("{other}"),
    }
    // The waisted cylinder (s = −4) overhangs above its waist.
    match PdeTube::new(
        &cylinder(32, -4.0),
        1.0,
        4,
        TubeKind::Boss,
        vec![],
        (128, TOL),
    )
    .unwrap_err()
    {
        TubeError::Overhang { lower, upper, .. } => assert!(lower >= -10.0 && upper < 0.0),
        other => panic!("{other}"),
    }
}

#[test]
fn a_trim_in_the_middle_overhangs_and_one_reaching_the_top_does_not() {
    let c = vase(64, false);
    let top = vec![rect(0.6, 1.2, 1.0, 2.0)];
    let t = PdeTube::new(&c, 1.0, 6, TubeKind::Boss, top, (512, TOL)).unwrap();
    // Below u = 0.6 (z = −6) one outline, above it one pie piece with its apex.
    assert_eq!(t.section(-7.0).len(), 1);
    let cut = t.section(-3.0);
    assert_eq!(cut.len(), 1);
    // The window spans 1 rad of 2π round a nearly round section: it removes
    // about a 2π-th of the area (to 10 %: the section is not a circle).
    let full = PdeTube::new(&c, 1.0, 6, TubeKind::Boss, vec![], (512, TOL)).unwrap();
    let share = 1.0 - net_area(&cut) / net_area(&full.section(-3.0));
    assert!((share * TAU - 1.0).abs() < 0.1, "{share}");
    let middle = vec![rect(0.3, 0.6, 1.0, 2.0)];
    match PdeTube::new(&c, 1.0, 6, TubeKind::Boss, middle, (512, TOL)).unwrap_err() {
        // The window's top edge is u = 0.6, z = 15·0.6 − 15 = −6.
        TubeError::Overhang { lower, upper, .. } => assert!(lower <= -6.0 && -6.0 <= upper),
        other => panic!("{other}"),
    }
}

#[test]
fn a_turning_spine_is_refused_at_its_turning_point() {
    // z(u) = Hermite(0, 10; −30, 10): z′ = −120u² + 160u − 30, root
    // u = (160 − √11200)/240 in (0, 1), where z turns back.
    let mut c = cylinder(16, 0.0);
    c.x1.iter_mut().for_each(|p| p[2] = 10.0);
    c.xu0.iter_mut().for_each(|p| p[2] = -30.0);
    c.xu1.iter_mut().for_each(|p| p[2] = 10.0);
    let u = (160.0 - 11200f64.sqrt()) / 240.0;
    let z = 10.0 * (-2.0 * u.powi(3) + 3.0 * u * u) - 30.0 * (u.powi(3) - 2.0 * u * u + u)
        + 10.0 * (u.powi(3) - u * u);
    match PdeTube::new(&c, 1.0, 4, TubeKind::Boss, vec![], (64, TOL)).unwrap_err() {
        TubeError::NotMonotone { z: got, u: gu } => {
            assert!((gu - u).abs() < 1e-12, "{gu} vs {u}");
            assert!((got - (z - 10.0)).abs() < 1e-9, "{got} vs {}", z - 10.0);
        }
        other => panic!("{other}"),
    }
}

#[test]
fn data_that_do_not_make_a_tube_are_typed_errors_naming_the_key() {
    let key = |c: &BoundaryCurves, trims: Vec<Vec<[f64; 2]>>, pt: (usize, f64)| match PdeTube::new(
        c,
        1.0,
        4,
        TubeKind::Boss,
        trims,
        pt,
    ) {
        Err(TubeError::Invalid { key, .. }) => key,
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    };
    let good = vase(32, false);
    let mut tilted = good.clone();
    tilted.x0[3][2] = 0.1;
    assert_eq!(key(&tilted, vec![], (64, TOL)), "x0");
    let mut slanted = good.clone();
    slanted.xu1[7][2] = 14.0;
    assert_eq!(key(&slanted, vec![], (64, TOL)), "xu1");
    assert_eq!(key(&good, vec![], (8, TOL)), "points");
    assert_eq!(
        key(&good, vec![vec![[0.0, 0.0], [1.0, 1.0]]], (64, TOL)),
        "trims"
    );
    assert!(matches!(
        PdeTube::new(&good, 1.0, 4, TubeKind::Boss, vec![], (64, 0.0)),
        Err(TubeError::Invalid { key: "tol", .. })
    ));
    let mut flat = good.clone();
    flat.x1.iter_mut().for_each(|p| p[2] = 0.0);
    assert_eq!(key(&flat, vec![], (64, TOL)), "x1");
    let mut nan = good;
    nan.x1[0][0] = f64::NAN;
    assert!(matches!(
        PdeTube::new(&nan, 1.0, 4, TubeKind::Boss, vec![], (64, TOL)),
        Err(TubeError::Pde(PdeError::Invalid { key: "x1", .. }))
    ));
}

#[test]
fn section_areas_match_closed_forms() {
    // The cylinder's section at u = ½ (z = −10) is a circle of the closed-form
    // radius r sampled at P equal angles: a regular P-gon, area (P/2) r² sin(2π/P).
    let (p, s) = (1000, 6.0);
    let t = unchecked(&cylinder(32, s), vec![], p);
    let r = waist(5.0, s, 1.0);
    assert!((t.u_of(-10.0) - 0.5).abs() < 1e-15);
    let a = net_area(&t.section(-10.0));
    let want = 0.5 * p as f64 * r * r * (TAU / p as f64).sin();
    assert!((a - want).abs() < 1e-9 * want, "{a} vs {want}");
    // Trimmed over v ∈ [1, 2]: the kept pie is the apex and m equal chords over
    // 2π − 1, m = ⌈(2π − 1)/2π · P⌉: area (m/2) r² sin((2π − 1)/m), within 1e-4 of
    // the sector r²(2π − 1)/2.
    let t = unchecked(&cylinder(32, s), vec![rect(0.3, 1.1, 1.0, 2.0)], p);
    let pie = t.section(-10.0);
    let m = ((TAU - 1.0) / TAU * p as f64).ceil();
    let want = 0.5 * m * r * r * ((TAU - 1.0) / m).sin();
    assert!((net_area(&pie) - want).abs() < 1e-9 * want);
    assert!((want / (0.5 * r * r * (TAU - 1.0)) - 1.0).abs() < 1e-4);
    // Below the trim (u = 0.2, z = −16) the whole circle.
    assert_eq!(t.section(-16.0).len(), 1);
    assert_eq!(t.section(-16.0)[0].len(), p);
    // The vase's bottom is the squircle: 4·10²·Γ(5/4)²/Γ(3/2) = 370.8149354602745
    // (measured 370.81476, −4.6e-7 relative: the 4096-gon's chords).
    let v = PdeTube::new(
        &vase(256, false),
        1.0,
        8,
        TubeKind::Boss,
        vec![],
        (4096, TOL),
    )
    .unwrap();
    let a = net_area(&v.section(-15.0));
    assert!((a - 370.8149354602745).abs() < 1e-5 * a, "{a}");
    // A mould's section is the boss's reversed.
    let m = PdeTube::new(
        &vase(256, true),
        1.0,
        8,
        TubeKind::Mould,
        vec![],
        (4096, TOL),
    )
    .unwrap();
    assert!((net_area(&m.section(0.0)) + a).abs() < 1e-9 * a);
}

#[test]
fn a_section_area_matches_a_pixel_count() {
    // Pixels of 0.04 mm whose centre is inside the vase's section at z = −7.5
    // (u = ½), inside meaning nearer the spine point than the surface at the
    // pixel's polar angle, the surface's polar radius interpolated linearly
    // from 20000 points X(½, v) (not the section's polygon).
    let t = PdeTube::new(
        &vase(128, false),
        1.0,
        8,
        TubeKind::Boss,
        vec![],
        (2048, TOL),
    )
    .unwrap();
    let s = t.surface();
    let c = s.spine().point(0.5);
    let n = 20000;
    let mut polar: Vec<(f64, f64)> = (0..n)
        .map(|j| {
            let p = s.point(0.5, TAU * j as f64 / n as f64);
            let (x, y) = (p[0] - c[0], p[1] - c[1]);
            (y.atan2(x).rem_euclid(TAU), x.hypot(y))
        })
        .collect();
    polar.sort_by(|a, b| a.0.total_cmp(&b.0));
    let radius = |th: f64| {
        let i = polar.partition_point(|q| q.0 < th);
        let (a, b) = (polar[(i + n - 1) % n], polar[i % n]);
        let span = (b.0 - a.0).rem_euclid(TAU);
        let f = if span > 0.0 {
            (th - a.0).rem_euclid(TAU) / span
        } else {
            0.0
        };
        a.1 + f * (b.1 - a.1)
    };
    let h = 0.04;
    let mut count = 0usize;
    for i in -300..300 {
        for j in -300..300 {
            let (x, y) = ((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
            if x.hypot(y) < radius(y.atan2(x).rem_euclid(TAU)) {
                count += 1;
            }
        }
    }
    let pixels = count as f64 * h * h;
    let shoelace = net_area(&t.section(-7.5));
    // Boundary pixels: perimeter ≈ 55 mm × 0.04 mm ≈ 2.2 mm² at worst, far less
    // on average; measured 221.562 vs 221.594 mm², 1.5e-4 relative.
    assert!(
        (pixels - shoelace).abs() < 1e-3 * shoelace,
        "{pixels} vs {shoelace}"
    );
}

#[test]
fn curves_running_clockwise_give_the_same_sections() {
    // The cylinder mirrored in y: v runs clockwise, so every section and pie
    // piece is reversed to keep the material on the left; areas unchanged.
    let c = cylinder(32, 6.0);
    let mut m = c.clone();
    for curve in [&mut m.x0, &mut m.x1, &mut m.xu0, &mut m.xu1] {
        curve.iter_mut().for_each(|p| p[1] = -p[1]);
    }
    for trims in [vec![], vec![rect(0.3, 1.1, 1.0, 2.0)]] {
        let (a, b) = (unchecked(&c, trims.clone(), 400), unchecked(&m, trims, 400));
        for z in [-16.0, -10.0, -3.0] {
            let (sa, sb) = (a.section(z), b.section(z));
            assert_eq!(sa.len(), sb.len());
            for (pa, pb) in sa.iter().zip(&sb) {
                let (aa, ab) = (polygon_area(pa), polygon_area(pb));
                assert!(
                    aa > 0.0 && (aa - ab).abs() < 1e-9 * aa,
                    "z = {z}: {aa} vs {ab}"
                );
            }
        }
    }
}
