//! Harmonic tensor-product Bézier patches (issue 18, seed paper 003): the
//! mould against the paper's n = 3 values, its row sums, symmetries and cap,
//! harmonicity of the patch, exact reproduction of harmonic polynomials, the
//! even-degree condition and the height range.

use crate::doc_figures;

use pfcam::sources::harmonic_bezier::polynomials::{self, bernstein_net, harmonic_basis};
use pfcam::sources::harmonic_bezier::{
    mould, solve_mould, Form, HarmonicError, HarmonicPatch, Mould, MAX_DEGREE, ROW_SUM_LIMIT,
};

use crate::common::{Rng, PFCAM};

/// Every (degree, form) pair the module accepts.
fn all_moulds() -> Vec<Mould> {
    (1..=MAX_DEGREE)
        .flat_map(|n| {
            let forms = if n % 2 == 0 {
                vec![Form::Square, Form::Raised]
            } else {
                vec![Form::Square]
            };
            forms.into_iter().map(move |f| mould(n, f).unwrap())
        })
        .collect()
}

fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

/// The paper's check for n = 3 (issue 18): P₁₁ = (4, 0, 0, 2 | 2, 0, 0, 1)/9
/// and P₁₀ = (4/3, −4/3, 2/3, 0 | 2/3, −2/3, 1/3, 0) on (P₀₀…P₀₃ | P₃₀…P₃₃),
/// with P_ij's i across the rows (the rows are i = 0 and i = 3).
#[test]
fn degree_three_matches_the_paper() {
    let m = mould(3, Form::Square).unwrap();
    let p11: Vec<f64> = [4.0, 0.0, 0.0, 2.0, 2.0, 0.0, 0.0, 1.0]
        .iter()
        .map(|c| c / 9.0)
        .collect();
    let p10 = [
        4.0 / 3.0,
        -4.0 / 3.0,
        2.0 / 3.0,
        0.0,
        2.0 / 3.0,
        -2.0 / 3.0,
        1.0 / 3.0,
        0.0,
    ];
    assert!(
        close(m.point(1, 1).unwrap(), &p11, 1e-14),
        "{:?}",
        m.point(1, 1)
    );
    assert!(
        close(m.point(1, 0).unwrap(), &p10, 1e-14),
        "{:?}",
        m.point(1, 0)
    );
    // Only this convention can give them: with i along the rows (prescribed
    // P_i0 and P_in) the paper's P₁₀ would be a prescribed point, not a
    // combination of others.
    assert_eq!(m.inner_index(0), (1, 0));
    assert!(m.point(0, 1).is_none());
}

/// Every row of every mould sums to 1 (a constant is harmonic), summed here
/// afresh from the coefficients, up to the cap.
#[test]
fn every_row_sums_to_one_up_to_the_cap() {
    for m in all_moulds() {
        for r in 0..m.rows() {
            let sum: f64 = m.row(r).iter().sum();
            assert!(
                (sum - 1.0).abs() <= ROW_SUM_LIMIT,
                "degree {} {:?} row {r}: {sum}",
                m.degree,
                m.form
            );
        }
        assert!(m.row_sum_error <= ROW_SUM_LIMIT);
    }
}

/// The cap is where the row sums fail: the degree above it breaks the
/// limit in both forms it has, and is refused with that reason.
#[test]
fn the_cap_is_where_f64_loses_the_row_sums() {
    let above = MAX_DEGREE + 1;
    let forms: &[Form] = if above % 2 == 0 {
        &[Form::Square, Form::Raised]
    } else {
        &[Form::Square]
    };
    for &f in forms {
        let e = solve_mould(above, f).unwrap().row_sum_error;
        assert!(e > ROW_SUM_LIMIT, "degree {above} {f:?}: {e:e}");
    }
    match mould(above, Form::Square) {
        Err(e @ HarmonicError::DegreeAboveCap { .. }) => {
            let text = e.to_string();
            assert!(text.starts_with("shape.degree: "), "{text}");
            assert!(text.contains("sum to 1 only within"), "{text}");
        }
        other => panic!("{other:?}"),
    }
    // A huge degree is refused at once, without building its system.
    assert!(matches!(
        mould(usize::MAX, Form::Square),
        Err(HarmonicError::DegreeAboveCap { .. })
    ));
    assert!(matches!(
        mould(0, Form::Square),
        Err(HarmonicError::DegreeTooLow { .. })
    ));
    assert!(matches!(
        mould(3, Form::Raised),
        Err(HarmonicError::RaisedOddDegree { .. })
    ));
}

/// i ↔ m − i swaps the two blocks; j ↔ n − j reverses the columns in each
/// block (the harmonic condition is symmetric under u → 1 − u, v → 1 − v).
#[test]
fn moulds_have_the_two_mirror_symmetries() {
    for m in all_moulds() {
        let (n, a) = (m.degree, m.across);
        let scale = (0..m.rows())
            .flat_map(|r| m.row(r).iter())
            .fold(1.0_f64, |s, c| s.max(c.abs()));
        // The solve's forward error grows with the degree (1.3e-11 of the
        // largest coefficient at n = 10, examples/harmonic_rowsums.rs).
        let tol = ROW_SUM_LIMIT * scale;
        for i in 1..a {
            for j in 0..=n {
                let p = m.point(i, j).unwrap();
                let (b0, b1) = p.split_at(n + 1);
                let swapped: Vec<f64> = b1.iter().chain(b0).copied().collect();
                let reversed: Vec<f64> = b0.iter().rev().chain(b1.iter().rev()).copied().collect();
                let q = m.point(a - i, j).unwrap();
                assert!(close(q, &swapped, tol), "n {n} {:?} ({i},{j})", m.form);
                let q = m.point(i, n - j).unwrap();
                assert!(close(q, &reversed, tol), "n {n} {:?} ({i},{j})", m.form);
            }
        }
    }
}

/// A patch with random rows for each accepted (degree, form); even square
/// patches get rows whose n-th differences agree.
fn random_patches(rng: &mut Rng) -> Vec<HarmonicPatch> {
    let mut out = Vec::new();
    for m in all_moulds() {
        let n = m.degree;
        let row0: Vec<f64> = (0..=n).map(|_| 10.0 * rng.range(-1.0, 1.0)).collect();
        let mut row1: Vec<f64> = (0..=n).map(|_| 10.0 * rng.range(-1.0, 1.0)).collect();
        if m.form == Form::Square && n % 2 == 0 {
            // Move row1's last point so that Δⁿrow1 = Δⁿrow0.
            let diff = |r: &[f64]| -> f64 {
                (0..=n)
                    .map(|j| (if (n - j) % 2 == 0 { 1.0 } else { -1.0 }) * binomial(n, j) * r[j])
                    .sum()
            };
            row1[n] += diff(&row0) - diff(&row1);
        }
        out.push(HarmonicPatch::new(n, m.form, [80.0, 50.0], &row0, &row1).unwrap());
    }
    out
}

/// Δh = h_uu + h_vv = 0 in the parameter plane at random points, to 1e-9 of
/// the second derivatives' size; first and second derivatives against central
/// differences of h, and the mm gradient against the parameter one.
#[test]
fn patches_are_harmonic_and_their_derivatives_are_right() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for p in random_patches(&mut rng) {
        for _ in 0..20 {
            let (u, v) = (rng.next(), rng.next());
            let d = p.param_derivatives(u, v);
            let size = d.h_uu.abs().max(d.h_vv.abs()).max(1.0);
            assert!(
                (d.h_uu + d.h_vv).abs() <= 1e-9 * size,
                "n {} {:?}: Δh = {:e} at ({u}, {v})",
                p.degree,
                p.form,
                d.h_uu + d.h_vv
            );
            let f = |u: f64, v: f64| p.param_derivatives(u, v).h;
            let e = 1e-4;
            let fd_u = (f(u + e, v) - f(u - e, v)) / (2.0 * e);
            let fd_v = (f(u, v + e) - f(u, v - e)) / (2.0 * e);
            let fd_uu = (f(u + e, v) - 2.0 * d.h + f(u - e, v)) / (e * e);
            let fd_vv = (f(u, v + e) - 2.0 * d.h + f(u, v - e)) / (e * e);
            let fd_uv = (f(u + e, v + e) - f(u + e, v - e) - f(u - e, v + e) + f(u - e, v - e))
                / (4.0 * e * e);
            let scale = (p.heights().iter().fold(1.0_f64, |a, h| a.max(h.abs()))) * 1e3;
            for (what, exact, fd, tol) in [
                ("h_u", d.h_u, fd_u, 1e-6),
                ("h_v", d.h_v, fd_v, 1e-6),
                ("h_uu", d.h_uu, fd_uu, 1e-4),
                ("h_vv", d.h_vv, fd_vv, 1e-4),
                ("h_uv", d.h_uv, fd_uv, 1e-4),
            ] {
                assert!(
                    (exact - fd).abs() <= tol * scale,
                    "n {} {what}: {exact} vs {fd}",
                    p.degree
                );
            }
            let [gx, gy] = p.gradient(v * 80.0, u * 50.0);
            assert!((gx - d.h_v / 80.0).abs() < 1e-12 * scale);
            assert!((gy - d.h_u / 50.0).abs() < 1e-12 * scale);
            assert!((p.height(v * 80.0, u * 50.0) - d.h).abs() < 1e-12 * scale);
        }
    }
}

/// Re and Im (u + iv)^k that fit bidegree (m, n) span the harmonic
/// polynomials of that bidegree; given their rows, each patch reproduces
/// their whole net (and so the polynomial), to 1e-9 of the net's size (the
/// mould's own accuracy, `examples/harmonic_rowsums.rs`). Their count is
/// 2(n + 1) for the unique moulds and 2n + 1 for the even square one: the
/// tests cover the whole space the mould acts on.
#[test]
fn harmonic_polynomials_are_reproduced_exactly() {
    for m in all_moulds() {
        let (n, a) = (m.degree, m.across);
        let basis = harmonic_basis(a, n);
        let unique = !(m.form == Form::Square && n % 2 == 0);
        assert_eq!(basis.len(), if unique { 2 * n + 2 } else { 2 * n + 1 });
        for poly in &basis {
            let exact = bernstein_net(poly, a, n);
            let w = n + 1;
            let p =
                HarmonicPatch::new(n, m.form, [30.0, 20.0], &exact[..w], &exact[a * w..]).unwrap();
            let tol = ROW_SUM_LIMIT * exact.iter().fold(1.0_f64, |s, c| s.max(c.abs()));
            assert!(
                close(p.heights(), &exact, tol),
                "n {n} {:?} {poly:?}",
                m.form
            );
            for (u, v) in [(0.3, 0.6), (0.77, 0.12), (0.5, 0.5)] {
                let h = p.height(v * 30.0, u * 20.0);
                assert!((h - polynomials::eval(poly, u, v)).abs() <= tol);
            }
        }
    }
}

/// u³ − 3uv² (Re (u + iv)³) from its two rows at u = 0 (h = 0) and u = 1
/// (h = 1 − 3v²), written out by hand: the patch is that cubic.
#[test]
fn the_cubic_u3_minus_3uv2() {
    // Bernstein coefficients of 1 − 3v² at degree 3: 1, 1, 0, −2.
    let p = HarmonicPatch::new(
        3,
        Form::Square,
        [1.0, 1.0],
        &[0.0; 4],
        &[1.0, 1.0, 0.0, -2.0],
    )
    .unwrap();
    let mut rng = Rng(7);
    for _ in 0..50 {
        let (x, y) = (rng.next(), rng.next());
        let (u, v) = (y, x);
        let expect = u * u * u - 3.0 * u * v * v;
        assert!((p.height(x, y) - expect).abs() < 1e-14);
        let [gx, gy] = p.gradient(x, y);
        assert!((gx - (-6.0 * u * v)).abs() < 1e-13);
        assert!((gy - (3.0 * u * u - 3.0 * v * v)).abs() < 1e-13);
    }
}

/// An even square patch needs equal n-th differences: refused with the
/// reason otherwise; accepted when they agree, and then the same surface as
/// the raised patch through the same rows (the n × n one raised to degree
/// n + 1 across is harmonic with those rows, and that patch is unique).
#[test]
fn even_square_patches_need_equal_nth_differences() {
    let row0 = [0.0, 1.0, 3.0, 2.0, 5.0];
    let row1 = [1.0, 0.0, 2.0, 2.0, 4.0];
    match HarmonicPatch::new(4, Form::Square, [40.0, 40.0], &row0, &row1) {
        Err(e @ HarmonicError::EvenRowsDisagree { .. }) => {
            let text = e.to_string();
            assert!(text.contains("4-th differences"), "{text}");
            assert!(text.contains("raised"), "{text}");
        }
        other => panic!("{other:?}"),
    }
    // Δ⁴row0 = 0 − 4 + 18 − 8 + 5 = 11; make row1's equal.
    // Δ⁴row1 = 1 − 0 + 12 − 8 + x = 5 + x: x = 6.
    let row1 = [1.0, 0.0, 2.0, 2.0, 6.0];
    let sq = HarmonicPatch::new(4, Form::Square, [40.0, 40.0], &row0, &row1).unwrap();
    let raised = HarmonicPatch::new(4, Form::Raised, [40.0, 40.0], &row0, &row1).unwrap();
    let mut rng = Rng(11);
    for _ in 0..30 {
        let (x, y) = (40.0 * rng.next(), 40.0 * rng.next());
        assert!((sq.height(x, y) - raised.height(x, y)).abs() < 1e-9);
    }
}

/// Input errors name the key.
#[test]
fn bad_rows_and_sizes_name_their_keys() {
    let r = [0.0; 4];
    let e = |res: Result<HarmonicPatch, HarmonicError>| res.unwrap_err().to_string();
    assert!(e(HarmonicPatch::new(
        3,
        Form::Square,
        [10.0, 10.0],
        &[0.0; 3],
        &r
    ))
    .starts_with("shape.row0: degree 3 needs 4 heights"));
    assert!(e(HarmonicPatch::new(
        3,
        Form::Square,
        [10.0, 10.0],
        &r,
        &[0.0; 5]
    ))
    .starts_with("shape.row1: "));
    assert!(e(HarmonicPatch::new(
        3,
        Form::Square,
        [10.0, 10.0],
        &r,
        &[0.0, f64::NAN, 0.0, 0.0]
    ))
    .starts_with("shape.row1[1]: "));
    assert!(e(HarmonicPatch::new(3, Form::Square, [0.0, 10.0], &r, &r)).starts_with("shape.size: "));
    assert!(e(HarmonicPatch::new(
        3,
        Form::Square,
        [10.0, f64::INFINITY],
        &r,
        &r
    ))
    .starts_with("shape.size: "));
    // A degree far out is refused before anything is sized from it.
    assert!(e(HarmonicPatch::new(
        usize::MAX,
        Form::Square,
        [10.0, 10.0],
        &r,
        &r
    ))
    .starts_with("shape.degree: "));
    let big = vec![0.0; MAX_DEGREE + 2];
    assert!(e(HarmonicPatch::new(
        MAX_DEGREE + 1,
        Form::Square,
        [10.0, 10.0],
        &big,
        &big
    ))
    .starts_with("shape.degree: "));
}

/// The range is the true max and min: at least every value on a 201 × 201
/// grid over the whole rectangle, at most a hair above the best of them, and
/// h at its argmax/argmin. The patches overshoot their rows.
#[test]
fn the_height_range_bounds_the_surface_and_overshoots_the_rows() {
    let mut rng = Rng(99);
    let mut overshoots = 0;
    for p in random_patches(&mut rng) {
        let r = p.height_range();
        let [sx, sy] = p.size;
        let k = 200;
        let (mut gmin, mut gmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for a in 0..=k {
            for b in 0..=k {
                let h = p.height(sx * a as f64 / k as f64, sy * b as f64 / k as f64);
                gmin = gmin.min(h);
                gmax = gmax.max(h);
            }
        }
        let scale = p.heights().iter().fold(1.0_f64, |s, h| s.max(h.abs()));
        assert!(r.max >= gmax - 1e-12 * scale && r.min <= gmin + 1e-12 * scale);
        // The grid's step is 1/200 of the side: near a smooth extremum it
        // misses at most a few 1e-5 of the scale.
        assert!(
            r.max - gmax <= 1e-3 * scale,
            "n {}: {} vs {gmax}",
            p.degree,
            r.max
        );
        assert!(
            gmin - r.min <= 1e-3 * scale,
            "n {}: {} vs {gmin}",
            p.degree,
            r.min
        );
        assert!((p.height(r.argmax[0], r.argmax[1]) - r.max).abs() < 1e-12 * scale);
        assert!((p.height(r.argmin[0], r.argmin[1]) - r.min).abs() < 1e-12 * scale);
        let w = p.degree + 1;
        let m = p.across();
        let rows = p.heights()[..w].iter().chain(&p.heights()[m * w..]);
        let row_max = rows.clone().fold(f64::NEG_INFINITY, |a, &h| a.max(h));
        let row_min = rows.fold(f64::INFINITY, |a, &h| a.min(h));
        if r.max > row_max + 1e-6 || r.min < row_min - 1e-6 {
            overshoots += 1;
        }
    }
    assert!(overshoots > 0, "no random patch left its rows' range");
}

/// The 3D control points (jX/n, iY/m, P_ij) are a parametric Bézier patch
/// whose points are (x, y, h(x, y)) (linear precision of Bernstein nets).
#[test]
fn the_3d_control_net_is_the_same_surface() {
    let row0 = [0.0, 2.0, -1.0, 4.0, 1.0, 0.5];
    let row1 = [3.0, 1.0, 0.0, 2.0, 2.0, 1.0];
    let p = HarmonicPatch::new(5, Form::Square, [60.0, 25.0], &row0, &row1).unwrap();
    let pts = p.control_points();
    let bern = |n: usize, i: usize, t: f64| {
        binomial(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
    };
    for (u, v) in [(0.2, 0.9), (0.6, 0.35)] {
        let mut s = [0.0; 3];
        for i in 0..=5 {
            for j in 0..=5 {
                let w = bern(5, i, u) * bern(5, j, v);
                for c in 0..3 {
                    s[c] += w * pts[i * 6 + j][c];
                }
            }
        }
        assert!((s[0] - 60.0 * v).abs() < 1e-12 && (s[1] - 25.0 * u).abs() < 1e-12);
        assert!((s[2] - p.height(s[0], s[1])).abs() < 1e-12);
    }
}

/// `pfcam harmonic-mould --degree 3 --json` gives the paper's P₁₁; the text
/// table has one line per inner point; a degree above the cap is a usage
/// error (exit 2) saying why.
#[test]
fn the_cli_prints_the_mould() {
    let out = std::process::Command::new(PFCAM)
        .args(["harmonic-mould", "--degree", "3", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["columns"][4], "P3,0");
    let inner = doc["inner"].as_array().unwrap();
    assert_eq!(inner.len(), 8);
    let p11 = inner.iter().find(|p| p["i"] == 1 && p["j"] == 1).unwrap();
    let c: Vec<f64> = p11["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap() * 9.0)
        .collect();
    assert!(
        close(&c, &[4.0, 0.0, 0.0, 2.0, 2.0, 0.0, 0.0, 1.0], 1e-13),
        "{c:?}"
    );

    let out = std::process::Command::new(PFCAM)
        .args(["harmonic-mould", "--degree", "4"])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("raised, 5 × 4"), "{text}");
    assert_eq!(text.lines().count(), 2 + 4 * 5, "{text}");

    let out = std::process::Command::new(PFCAM)
        .args(["harmonic-mould", "--degree", &(MAX_DEGREE + 1).to_string()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("--degree: ") && err.contains("sum to 1 only within"),
        "{err}"
    );
}

/// docs/method.md §14 quotes the row-sum error per degree: each figure of
/// 1e-13 or more (below that it is rounding noise that differs between
/// machines) within a factor 4 of a fresh solve, and the cap it names is
/// `MAX_DEGREE`.
#[test]
fn the_method_doc_quotes_the_measured_row_sums() {
    let doc = doc_figures::read("docs/method.md");
    // Up to the next section (§15's tables have numbers in their first cells too).
    let section = doc_figures::after(&doc, "docs/method.md", "## 14. Harmonic Bézier")
        .split("\n## ")
        .next()
        .unwrap_or_default();
    let mut checked = 0;
    for line in section.lines().filter(|l| l.starts_with("| ")) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let (Ok(n), Some(form)) = (cells[0].parse::<usize>(), cells.get(1)) else {
            continue;
        };
        let form = if *form == "raised" {
            Form::Raised
        } else {
            Form::Square
        };
        let quoted: f64 = cells[2].parse().unwrap();
        let now = solve_mould(n, form).unwrap().row_sum_error;
        if quoted >= 1e-13 {
            assert!(
                now <= 4.0 * quoted && now >= quoted / 4.0,
                "docs/method.md §14, n = {n} {form:?}: the doc says {quoted:e}, now {now:e}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 8, "only {checked} rows checked");
    let cap = doc_figures::number_after(section, "docs/method.md", "the cap is degree");
    assert_eq!(cap, MAX_DEGREE.to_string());
}

/// A worked example with a closed form (docs/method.md §14): row0 = 0 and
/// row1 = (0, 10, 10, 0) over 40 × 40 mm give h = 10(u³ − 3uv²) + 30uv − 10u
/// (harmonic, 0 at u = 0, 30v(1 − v) at u = 1). It dips below both rows on
/// the edge x = 0, h = 10(u³ − u), to −20/(3√3) at u = 1/√3, and its top is
/// the row1 curve's 7.5 at v = ½.
#[test]
fn the_range_of_the_worked_example_is_its_closed_form() {
    let p = HarmonicPatch::new(
        3,
        Form::Square,
        [40.0, 40.0],
        &[0.0; 4],
        &[0.0, 10.0, 10.0, 0.0],
    )
    .unwrap();
    let mut rng = Rng(5);
    for _ in 0..20 {
        let (u, v) = (rng.next(), rng.next());
        let exact = 10.0 * (u * u * u - 3.0 * u * v * v) + 30.0 * u * v - 10.0 * u;
        assert!((p.height(40.0 * v, 40.0 * u) - exact).abs() < 1e-13);
    }
    let r = p.height_range();
    let s3 = 3f64.sqrt();
    assert!((r.min + 20.0 / (3.0 * s3)).abs() < 1e-12, "{}", r.min);
    assert!(r.argmin[0] == 0.0 && (r.argmin[1] - 40.0 / s3).abs() < 1e-6);
    assert!((r.max - 7.5).abs() < 1e-12 && (r.argmax[0] - 20.0).abs() < 1e-6);
    assert_eq!(r.argmax[1], 40.0);
}
