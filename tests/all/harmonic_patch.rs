//! A harmonic patch as a job's part (`shape.kind = "harmonic-bezier"`): the
//! job's errors naming keys.

use pfcam::job::{parse_job, Job};
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
