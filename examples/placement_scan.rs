//! Where the shape field's points sit, per character and N, in the paired
//! layout a job uses: the least distance from a charge to a collocation or
//! check point (relative to the outer radius R), the charges the guard had to
//! move, and (with `solve`) the max boundary error.
//! `cargo run --release --example placement_scan -- FONT.ttf CHARS N1,N2,... [solve]`
//!
//! With `refine` in place of `solve`, `N1,N2` are the refined layout's first
//! uniform charges and its cap (`field::refine`, docs/method.md §3d): each
//! character is refined to `TARGET` (default 1e-6) and its error, N, solves,
//! time, clusters' pairs and contours' uniform charges are printed.
use std::path::Path;

fn main() {
    let mut args = std::env::args().skip(1);
    let font = args
        .next()
        .expect("usage: placement_scan FONT CHARS NS [solve]");
    let chars = args.next().expect("CHARS");
    let ns: Vec<usize> = args
        .next()
        .expect("NS")
        .split(',')
        .map(|s| s.parse().expect("N"))
        .collect();
    let mode = args.next().unwrap_or_default();
    let solve = mode == "solve" || mode == "worst";
    let abs = std::fs::canonicalize(&font).expect("font file");
    for c in chars.chars() {
        let text = format!(
            "[shape]\ntext = {:?}\nfont = {:?}\nheight = 50.0\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"profile\"\ndepth = 3.0\n",
            c.to_string(),
            abs.display().to_string()
        );
        let job = pfcam::job::parse_job(&text, "g", Path::new(".")).expect("job");
        let (shape, _) = pfcam::pipeline::job_shape(&job, &mut |_| {}).expect("shape");
        let tol = job.operation.tolerance * 0.25;
        let b = pfcam::pipeline::boundary_for(&shape, tol).expect("boundary");
        let r = b.radius;
        let prep = pfcam::field::Prepared::new(b).expect("prepared");
        if mode == "refine" {
            refine(c, &prep, &ns);
            continue;
        }
        for &n in &ns {
            let h = prep.perimeter() / n as f64;
            let lay = pfcam::field::Layout {
                n_total: n,
                distance: std::env::var("DFAC")
                    .ok()
                    .and_then(|v| v.parse::<f64>().ok())
                    .unwrap_or(2.0)
                    * h,
                corner_clusters: true,
                corner_fraction: 0.4,
                pairs: true,
            };
            let pr = match prep.problem(&lay) {
                Ok(p) => p,
                Err(e) => {
                    println!("{c} N {n}: {e}");
                    continue;
                }
            };
            let sep = pfcam::field::setup::min_separation(&pr, 1e-6 * r) / r;
            let e = if solve {
                match pfcam::field::mfs::solve(&pr) {
                    Ok(s) if mode == "worst" => {
                        let mut errs: Vec<(f64, pfcam::geometry::Vec2)> = pr
                            .checks
                            .iter()
                            .map(|c| ((s.field.value(c.p) - c.value).abs(), c.p))
                            .collect();
                        errs.sort_by(|a, b| b.0.total_cmp(&a.0));
                        let mut out = format!("{:.2e}\n", s.max_error);
                        for (e, p) in errs.iter().take(3) {
                            out += &format!("    {e:.2e} at ({:.4}, {:.4})\n", p.x, p.y);
                        }
                        let w = errs[0].1;
                        for (k, q) in pr.charges.iter().enumerate() {
                            if q.dist(w) < 1.0 {
                                out += &format!(
                                    "      charge {k} at ({:.4}, {:.4}) dist {:.3e}\n",
                                    q.x,
                                    q.y,
                                    q.dist(w)
                                );
                            }
                        }
                        for c in &prep.boundary.contours {
                            let n = c.segments.len();
                            for i in 0..n {
                                let (a, b) = (&c.segments[i], &c.segments[(i + 1) % n]);
                                if b.start().dist(w) < 0.6 {
                                    let (ti, to) =
                                        (a.eval(1.0) - a.eval(0.999), b.eval(0.001) - b.eval(0.0));
                                    let turn = ti.cross(to).atan2(ti.dot(to));
                                    out += &format!("      join ({:.4}, {:.4}) turn {turn:.3} in {a:?}\n       out {b:?}\n", b.start().x, b.start().y);
                                }
                            }
                        }
                        for poly in prep.polygons() {
                            for v in poly {
                                if v.dist(w) < 0.6 {
                                    out += &format!("      vertex ({:.4}, {:.4})\n", v.x, v.y);
                                }
                            }
                        }
                        out
                    }
                    Ok(s) => format!(
                        "{:.2e}{}",
                        s.max_error,
                        if s.well_conditioned {
                            ""
                        } else {
                            " (fallback)"
                        }
                    ),
                    Err(e) => format!("{e}"),
                }
            } else {
                String::new()
            };
            println!("{c} N {n}: separation {sep:.1e} R, moved {}  {e}", pr.moved);
        }
    }
}

/// The refined layout of one character (`refine` mode).
fn refine(c: char, prep: &pfcam::field::Prepared, ns: &[usize]) {
    let target: f64 = std::env::var("TARGET")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1e-6);
    let cap = ns.get(1).copied().unwrap_or(4000);
    let t0 = std::time::Instant::now();
    let r = pfcam::field::refine::refine(prep, ns[0], target, cap, |pr| {
        pfcam::field::mfs::solve(pr).map(|s| {
            let e = s.errors.clone();
            (s, e)
        })
    });
    match r {
        Ok(r) => {
            println!(
                "{c} refine: {:.2e} N {} solves {} {:.2} s{} pairs {:?} contour {:?}",
                r.max_error,
                r.problem.charges.len(),
                r.solves,
                t0.elapsed().as_secs_f64(),
                if r.out.well_conditioned {
                    ""
                } else {
                    " (fallback)"
                },
                r.refinement.pairs,
                r.refinement.contour
            );
            if std::env::var("WORST").is_ok() {
                worst(prep, &r.problem, &r.out.errors, &r.out.field);
            }
        }
        Err(e) => println!("{c} refine: {e}"),
    }
}

/// The worst check points, each with its nearest sharp vertex of the
/// flattened outline (turn > 0.3 rad) and the nearest charge.
fn worst(
    prep: &pfcam::field::Prepared,
    pr: &pfcam::field::mfs::Problem,
    errors: &[f64],
    field: &pfcam::field::mfs::Field,
) {
    let mut sharp = Vec::new();
    for poly in prep.polygons() {
        let n = poly.len();
        for i in 0..n {
            let (a, b, c) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
            let (u, v) = ((b - a).normalized(), (c - b).normalized());
            let turn = u.cross(v).atan2(u.dot(v));
            if turn.abs() > 0.3 {
                sharp.push((b, turn));
            }
        }
    }
    let mut idx: Vec<usize> = (0..errors.len()).collect();
    idx.sort_by(|&a, &b| errors[b].total_cmp(&errors[a]));
    for &i in idx.iter().take(10) {
        let p = pr.checks[i].p;
        let (v, t) = sharp
            .iter()
            .min_by(|a, b| a.0.dist(p).total_cmp(&b.0.dist(p)))
            .copied()
            .unwrap_or((p, 0.0));
        let q = pr
            .charges
            .iter()
            .min_by(|a, b| a.dist(p).total_cmp(&b.dist(p)))
            .copied()
            .unwrap();
        let cp = pr
            .colloc
            .iter()
            .map(|c| c.p.dist(p))
            .fold(f64::INFINITY, f64::min);
        let g = field.value_grad(p).1.norm();
        println!(
            "  {:.2e} at ({:.3}, {:.3}): sharp vertex {:.3e} mm away, turn {:.2}; nearest charge {:.3e} mm, nearest colloc {:.3e} mm; |grad u| {:.3e} /mm, e/|grad u| {:.2e} mm",
            errors[i], p.x, p.y, v.dist(p), t, q.dist(p), cp, g, errors[i] / g
        );
    }
}
