//! `pfcam surface`: every boss and cavity job in jobs/ gives a closed,
//! consistently oriented mesh with no degenerate triangle, the volume an
//! independent grid estimate gives, vertices on the level curves, and a binary
//! STL that reads back the same; the command refuses to overwrite a foreign file
//! and writes nothing for a bad job.

use pfcam::field::isolines::Grid;
use pfcam::geometry::{polygon_winding_number, ShapeSource, Vec2};
use pfcam::job::{parse_job, Job, OperationKind};
use pfcam::surface::{
    edge_use_counts, is_watertight, job_surface, read_stl, stl_bytes, weld, JobSurface, Mesh,
    SurfaceOptions,
};
use std::fs;
use std::path::Path;

use crate::common::{pfcam, scratch, shipped_jobs};
use crate::doc_figures;

/// Every job in jobs/ of the given kind whose part is the MFS field's S2
/// (the directory is read, not listed here); a height field's block is
/// checked in tests/all/harmonic_patch.rs and tests/all/polyharmonic.rs, a
/// PDE tube's part in tests/all/pde_job.rs.
fn jobs_of(kind: OperationKind) -> Vec<Job> {
    shipped_jobs()
        .into_iter()
        .filter(|j| j.operation.kind == kind)
        .filter(|j| {
            !matches!(
                j.shape,
                ShapeSource::HarmonicBezier(_)
                    | ShapeSource::Polyharmonic(_)
                    | ShapeSource::PdeTube(_)
            )
        })
        .collect()
}

fn build(job: &Job) -> JobSurface {
    job_surface(job, &SurfaceOptions::default(), &mut |_| {})
        .unwrap_or_else(|e| panic!("{}: {e}", job.name))
}

/// Closed and consistently oriented, checked three ways: each undirected edge
/// is used by exactly two triangles, each directed edge by exactly one, and
/// `is_watertight` agrees; and no triangle is degenerate.
fn assert_closed(name: &str, mesh: &Mesh) {
    let directed = edge_use_counts(&mesh.triangles);
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "{name}: directed edge {a}→{b} used {n} times");
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        assert_eq!(
            n + back,
            2,
            "{name}: edge {a}–{b} shared by {} triangles",
            n + back
        );
    }
    assert!(is_watertight(&mesh.triangles), "{name}");
    assert_eq!(
        mesh.degenerate_triangles(),
        0,
        "{name}: degenerate triangles"
    );
    let min_area = (0..mesh.triangles.len())
        .map(|t| mesh.area(t))
        .fold(f64::INFINITY, f64::min);
    assert!(
        min_area > 0.0,
        "{name}: smallest triangle area {min_area:e}"
    );
}

/// The volume of the part from u alone: the stock's bottom to z(u(x, y)) by the
/// midpoint rule on a grid of spacing about `h` (u sampled by `Grid::sample`,
/// the material pinned to 1, z from φ directly).
fn reference_volume(js: &JobSurface, job: &Job, h: f64) -> (f64, f64) {
    let s = &js.surface;
    let (lo, hi) = (s.stock_lo, s.stock_hi);
    let n = ((hi.x - lo.x) / h).ceil();
    let h = (hi.x - lo.x) / n;
    let half = Vec2::new(h / 2.0, h / 2.0);
    let g = Grid::sample(&js.field, lo + half, hi - half, h, &js.glyphs);
    let profile = job.profile.as_ref().expect("profile");
    let depth = profile.depth();
    let top = job.stock.top;
    let z = |u: f64| {
        if job.operation.kind == OperationKind::Cavity {
            top - depth - profile.z(u)
        } else {
            top + profile.z(u)
        }
    };
    let floor = top - depth;
    let (mut v, mut raised) = (0.0, 0.0);
    for j in 0..g.ny {
        let y0 = lo.y + h * j as f64;
        let wy = (hi.y - y0).clamp(0.0, h);
        for i in 0..g.nx {
            let x0 = lo.x + h * i as f64;
            let wx = (hi.x - x0).clamp(0.0, h);
            let zz = z(g.values[j * g.nx + i]);
            v += (zz - s.z_bottom) * wx * wy;
            raised += (zz - floor) * wx * wy;
        }
    }
    (v, raised)
}

/// z of the level s: φ(s) from the stock top (mirrored for a cavity).
fn js_z(job: &Job, s: f64) -> f64 {
    let p = job.profile.as_ref().expect("profile");
    if job.operation.kind == OperationKind::Cavity {
        job.stock.top - p.depth() - p.z(s)
    } else {
        job.stock.top + p.z(s)
    }
}

/// Every check on one job's surface; returns (triangles, relative volume error).
fn check_job(job: &Job) -> (usize, f64) {
    let t0 = std::time::Instant::now();
    let js = build(job);
    let t_build = t0.elapsed().as_secs_f64();
    let s = &js.surface;
    let mesh = &s.mesh;
    let name = &job.name;
    assert_closed(name, mesh);
    assert!(mesh.check().is_ok(), "{name}");

    // The box: the stock rectangle, from the bottom to the stock top.
    let (lo, hi) = mesh.bbox().expect("vertices");
    let depth = job.profile.as_ref().expect("profile").depth();
    assert_eq!([lo[0], lo[1]], [s.stock_lo.x, s.stock_lo.y], "{name}");
    assert_eq!([hi[0], hi[1]], [s.stock_hi.x, s.stock_hi.y], "{name}");
    assert!(
        (lo[2] - (job.stock.top - depth - 2.0)).abs() < 1e-12,
        "{name}"
    );
    assert!((hi[2] - job.stock.top).abs() < 1e-12, "{name}");

    // Volume: positive, and within 0.2 % of the raised part's volume of the
    // independent estimate (see docs/method.md for the figures measured).
    let t1 = std::time::Instant::now();
    let v = mesh.volume();
    let (v_ref, raised) = reference_volume(&js, job, 0.2);
    let err = (v - v_ref).abs() / raised;
    assert!(v > 0.0, "{name}: volume {v}");
    assert!(
        err < 2e-3,
        "{name}: volume {v:.1} mm³, estimate {v_ref:.1} mm³ (raised part {raised:.1} mm³): {:.3} %",
        100.0 * err
    );
    let t_ref = t1.elapsed().as_secs_f64();

    // Vertices on the level curves: u = s_k there (u pinned to 1 in the material).
    let u = |p: Vec2| {
        let w: i32 = js.glyphs.iter().map(|g| polygon_winding_number(g, p)).sum();
        if w != 0 {
            1.0
        } else {
            js.field.value(p)
        }
    };
    // Where u jumps from below s_k to the material's 1 (Γ(s_k) closer to 1 than
    // the field's boundary error), the level's vertex is on the outline instead.
    let to_outline = |p: Vec2| {
        js.glyphs
            .iter()
            .flat_map(|g| (0..g.len()).map(move |i| (g[i], g[(i + 1) % g.len()])))
            .map(|(a, b)| {
                let d = b - a;
                let t = ((p - a).dot(d) / d.norm2()).clamp(0.0, 1.0);
                p.dist(a + d * t)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (mut worst, mut moved, mut on_outline) = (0.0_f64, 0, 0);
    for &(vi, k) in &s.crossings {
        let sk = s.levels[k];
        let p = mesh.vertices[vi as usize];
        let p = Vec2::new(p[0], p[1]);
        assert_eq!(mesh.vertices[vi as usize][2], js_z(job, sk), "{name}");
        let e = (u(p) - sk).abs();
        if sk >= 1.0 - 1e-12 || e > 1e-4 {
            let d = to_outline(p);
            // (at most T_MIN of its edge off, where kept clear of a grid point)
            let limit = 1.0001 * pfcam::surface::T_MIN * pfcam::surface::DEFAULT_RESOLUTION;
            assert!(
                d < limit,
                "{name}: level {sk}: |u − s_k| = {e:e}, {d:e} mm from the outline"
            );
            on_outline += 1;
            continue;
        }
        worst = worst.max(e);
        if e > 1e-9 {
            moved += 1;
        }
    }
    assert!(!s.crossings.is_empty(), "{name}");
    assert!(worst < 1e-4, "{name}: |u − s_k| up to {worst:e}");
    assert!(
        (moved as f64) < 0.01 * s.crossings.len() as f64,
        "{name}: {moved} of {} crossings off their level by more than 1e-9",
        s.crossings.len()
    );

    // The written file reads back: same triangles, closed after welding its
    // 32-bit vertices, normals by the right-hand rule.
    let bytes = stl_bytes(mesh, name);
    assert_eq!(bytes.len(), 84 + 50 * mesh.triangles.len());
    let (header, tris) = read_stl(&bytes).expect("read back");
    assert!(header.starts_with(format!("pfcam {name}").as_bytes()));
    assert_eq!(tris.len(), mesh.triangles.len(), "{name}");
    let welded = weld(&tris);
    assert_eq!(
        welded.vertices.len(),
        mesh.vertices.len(),
        "{name}: welding merged vertices"
    );
    assert_closed(&format!("{name} (STL)"), &welded);
    for t in &tris {
        let [a, b, c] = t.corners.map(|p| p.map(f64::from));
        let n = [
            (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
            (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]),
        ];
        let dot: f64 = (0..3).map(|i| n[i] * f64::from(t.normal[i])).sum();
        assert!(dot > 0.0, "{name}: stored normal against the winding");
    }
    eprintln!(
        "{name}: {} triangles, {} vertices, {} levels, grid {}×{}, volume {v:.1} mm³ vs {v_ref:.1} mm³ (error {:.1e} of the raised {raised:.1} mm³), |u − s_k| ≤ {worst:.1e} ({moved} of {} crossings moved, {on_outline} on the outline), build {t_build:.2} s, estimate {t_ref:.2} s",
        mesh.triangles.len(),
        mesh.vertices.len(),
        s.levels.len(),
        s.grid.0,
        s.grid.1,
        err,
        s.crossings.len()
    );
    let figures = Figures {
        triangles: mesh.triangles.len(),
        vertices: mesh.vertices.len(),
        stl_bytes: bytes.len(),
        levels: s.levels.len(),
        grid: [s.grid.0, s.grid.1],
        crossings: [moved, s.crossings.len()],
        worst_off_level: worst,
        volume: v,
        volume_error: err,
        raised,
    };
    figures.check_the_docs(name);
    (mesh.triangles.len(), err)
}

/// What `check_job` measures of a job's mesh, for the docs that quote it.
struct Figures {
    triangles: usize,
    vertices: usize,
    stl_bytes: usize,
    levels: usize,
    grid: [usize; 2],
    /// Crossings moved off their level by more than 1e-9, of all crossings.
    crossings: [usize; 2],
    worst_off_level: f64,
    volume: f64,
    volume_error: f64,
    raised: f64,
}

impl Figures {
    /// README.md and docs/method.md §9 ("The modelled surface") quote
    /// mfs-sign's mesh, q-sign's volume and the letter I's: the figures
    /// there are this job's (`cargo test --release --test all surface:: --
    /// --nocapture` prints them).
    fn check_the_docs(&self, name: &str) {
        let method = doc_figures::read("docs/method.md");
        let surface = doc_figures::after(&method, "docs/method.md", "### The modelled surface");
        let count = |marker: &str, n: usize| -> Vec<usize> {
            doc_figures::numbers_after(surface, "docs/method.md", marker, n)
                .iter()
                .map(|f| f.parse().expect(f))
                .collect()
        };
        let figure = |what: &str, marker: &str, value: f64| {
            let stated = doc_figures::number_after(surface, "docs/method.md", marker);
            doc_figures::assert_figure(
                &format!("docs/method.md §9, {name}'s {what}"),
                &stated,
                value,
            );
        };
        match name {
            "mfs-sign" => {
                let readme = doc_figures::read("README.md");
                let stated = doc_figures::numbers_after(&readme, "README.md", "For mfs-sign:", 2);
                let what = "README.md, mfs-sign's STL";
                assert_eq!(stated[0].parse().ok(), Some(self.triangles), "{what}");
                doc_figures::assert_figure(what, &stated[1], self.stl_bytes as f64 / 1e6);
                let levels = doc_figures::numbers_after(
                    surface,
                    "docs/method.md",
                    "1/16 of the range apart in s:",
                    1,
                );
                assert_eq!(levels[0].parse().ok(), Some(self.levels), "{name}: levels");
                assert_eq!(
                    count("On mfs-sign (0.4 mm grid,", 2),
                    self.grid,
                    "{name}: grid"
                );
                assert_eq!(
                    count("this gives", 2),
                    [self.triangles, self.vertices],
                    "{name}: mesh"
                );
                assert_eq!(
                    count("On mfs-sign this moves", 2),
                    self.crossings,
                    "{name}: crossings"
                );
                figure(
                    "crossings off their level",
                    "crossings; |u − s_k| ≤",
                    self.worst_off_level,
                );
                figure("volume", "The enclosed volume,", self.volume);
                let stated =
                    doc_figures::numbers_after(surface, "docs/method.md", "on a 0.2 mm grid to", 2);
                doc_figures::assert_figure(
                    "docs/method.md §9, mfs-sign's volume error",
                    &stated[0],
                    self.volume_error,
                );
                doc_figures::assert_figure(
                    "docs/method.md §9, mfs-sign's raised part",
                    &stated[1],
                    self.raised,
                );
            }
            "q-sign" | "mfs-mould" => {
                let marker = if name == "q-sign" {
                    "(q-sign:"
                } else {
                    "the mould, mfs-mould:"
                };
                let stated = doc_figures::numbers_after(surface, "docs/method.md", marker, 2);
                let what = format!("docs/method.md §9, {name}'s volume error and raised part");
                doc_figures::assert_figure(&what, &stated[0], self.volume_error);
                doc_figures::assert_figure(&what, &stated[1], self.raised);
            }
            "i-boss" => figure(
                "volume error",
                "with a linear profile is off by",
                self.volume_error,
            ),
            _ => {}
        }
    }
}

#[test]
fn every_boss_job_is_watertight_with_the_right_volume() {
    let jobs = jobs_of(OperationKind::Boss);
    assert!(!jobs.is_empty(), "no boss job in jobs/");
    for job in &jobs {
        check_job(job);
    }
}

#[test]
fn every_cavity_job_is_watertight_with_the_right_volume() {
    let jobs = jobs_of(OperationKind::Cavity);
    assert!(!jobs.is_empty(), "no cavity job in jobs/");
    for job in &jobs {
        check_job(job);
    }
}

/// A linear profile's top level is s = 1, the glyph's outline itself.
const LETTER_I: &str = "[job]\nname = \"i-boss\"\n[shape]\ntext = \"I\"\nheight = 20.0\n\
    [tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 2.0\n\
    [profile]\nkind = \"linear\"\ns_bottom = 0.95\n";

#[test]
fn linear_profiles_with_their_top_on_the_outline_are_closed_too() {
    for kind in ["boss", "cavity"] {
        let text = LETTER_I
            .replace("\"boss\"", &format!("\"{kind}\""))
            .replace("i-boss", &format!("i-{kind}"));
        let job = parse_job(&text, "i", Path::new(".")).expect("job");
        check_job(&job);
        let js = build(&job);
        // The outline is a level: some vertices lie on it.
        let on_outline = js
            .surface
            .crossings
            .iter()
            .filter(|&&(_, k)| js.surface.levels[k] == 1.0)
            .count();
        assert!(on_outline > 0, "{kind}");
    }
}

#[test]
fn the_stock_is_the_one_pfcam_run_cuts() {
    let job = &jobs_of(OperationKind::Boss)[0];
    let js = build(job);
    let out = pfcam::pipeline::run(job, &mut |_| {}).expect("run");
    let (lo, hi) = out.stock.expect("stock");
    assert_eq!((js.surface.stock_lo, js.surface.stock_hi), (lo, hi));
}

#[test]
fn the_command_writes_its_own_files_and_refuses_foreign_ones() {
    let dir = scratch("surface", "overwrite");
    fs::write(dir.join("i.toml"), LETTER_I).expect("job");
    // A new file; the summary line names the counts.
    let o = pfcam(&["surface", "i.toml", "-o", "i.stl", "-q"], &dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let first = fs::read(dir.join("i.stl")).expect("written");
    let (_, tris) = read_stl(&first).expect("STL");
    assert!(is_watertight(&weld(&tris).triangles));
    // Its own file is replaced without --force, and the summary says what it wrote.
    let o = pfcam(&["surface", "i.toml", "-o", "i.stl"], &dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(
        summary.contains("triangles") && summary.contains("watertight"),
        "{summary}"
    );
    // A foreign file is not, without --force: exit 3, the file untouched.
    fs::write(dir.join("mine.stl"), b"solid hand made\nendsolid\n").expect("foreign");
    let o = pfcam(&["surface", "i.toml", "-o", "mine.stl", "-q"], &dir);
    assert_eq!(o.status.code(), Some(3));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--force"), "{err}");
    assert_eq!(
        fs::read(dir.join("mine.stl")).expect("still there"),
        b"solid hand made\nendsolid\n"
    );
    let o = pfcam(
        &["surface", "i.toml", "-o", "mine.stl", "-q", "--force"],
        &dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(fs::read(dir.join("mine.stl")).expect("replaced"), first);
    // Nothing else was left in the directory (no temporary files).
    let mut names: Vec<String> = fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["i.stl", "i.toml", "mine.stl"]);
}

#[test]
fn bad_jobs_write_nothing() {
    let dir = scratch("surface", "bad");
    let cases = [
        (
            "profile.toml",
            "[shape]\ntext = \"I\"\nheight = 20.0\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 2.0\n"
                .to_string(),
            "operation.kind = \"profile\" has no modelled surface; use a boss or cavity job",
        ),
        (
            "typo.toml",
            LETTER_I.replace("depth = 2.0", "depth = -2.0"),
            "operation.depth",
        ),
        (
            "syntax.toml",
            LETTER_I.replace("height = 20.0", "height = = 20.0"),
            "syntax.toml:",
        ),
    ];
    for (file, text, needle) in cases {
        fs::write(dir.join(file), text).expect("job");
        let o = pfcam(&["surface", file, "-o", "out/x.stl"], &dir);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{file}: {err}");
        assert!(err.contains(needle), "{file}: {err}");
        assert!(!dir.join("out").exists(), "{file}: wrote something");
    }
    let o = pfcam(
        &["surface", "typo.toml", "-o", "x.stl", "--resolution", "0"],
        &dir,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(!dir.join("x.stl").exists());
}

#[test]
fn same_job_same_stl_on_any_thread_count() {
    let job = parse_job(LETTER_I, "i", Path::new(".")).expect("job");
    let bytes: Vec<Vec<u8>> = [1, 3]
        .iter()
        .map(|&n| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .expect("pool");
            pool.install(|| stl_bytes(&build(&job).surface.mesh, &job.name))
        })
        .collect();
    assert!(bytes[0] == bytes[1], "the STL depends on the thread count");
}
