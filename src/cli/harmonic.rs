//! `pfcam harmonic-mould --degree N [--form square|raised] [--json]`: the
//! harmonic Bézier mould of one degree (docs/method.md §14), as a table or
//! as JSON with each inner control point's (i, j) and coefficients.

use super::{stdout_line, UsageError};
use anyhow::Result;
use pfcam::sources::harmonic_bezier::{mould, Form, Mould};
use serde::Serialize;

/// One inner control point in the JSON.
#[derive(Serialize)]
struct Inner<'a> {
    i: usize,
    j: usize,
    coefficients: &'a [f64],
}

/// The JSON document.
#[derive(Serialize)]
struct MouldJson<'a> {
    degree: usize,
    across: usize,
    form: &'static str,
    columns: Vec<String>,
    row_sum_error: f64,
    inner: Vec<Inner<'a>>,
}

/// Print the mould. `form` is "square" or "raised" (clap checks); None is
/// square for odd degrees and raised for even ones (the unique mould).
pub fn cmd_harmonic_mould(degree: usize, form: Option<&str>, json: bool) -> Result<()> {
    let form = match form {
        Some("square") => Form::Square,
        Some(_) => Form::Raised,
        None if degree % 2 == 1 => Form::Square,
        None => Form::Raised,
    };
    let m = mould(degree, form).map_err(|e| {
        let text = e.to_string();
        let text = text.replacen("shape.degree:", "--degree:", 1);
        UsageError(text.replacen("shape.form:", "--form:", 1))
    })?;
    let columns = column_names(&m);
    if json {
        let doc = MouldJson {
            degree: m.degree,
            across: m.across,
            form: m.form.name(),
            columns,
            row_sum_error: m.row_sum_error,
            inner: (0..m.rows())
                .map(|r| {
                    let (i, j) = m.inner_index(r);
                    Inner {
                        i,
                        j,
                        coefficients: m.row(r),
                    }
                })
                .collect(),
        };
        return stdout_line(&serde_json::to_string_pretty(&doc)?);
    }
    stdout_line(&table(&m, &columns))
}

/// "P0,0" … "P0,n", "Pm,0" … "Pm,n".
fn column_names(m: &Mould) -> Vec<String> {
    [0, m.across]
        .iter()
        .flat_map(|i| (0..=m.degree).map(move |j| format!("P{i},{j}")))
        .collect()
}

/// The text table: a header line, the column names, one line per inner point.
fn table(m: &Mould, columns: &[String]) -> String {
    let cells: Vec<Vec<String>> = (0..m.rows())
        .map(|r| m.row(r).iter().map(|&c| six_places(c)).collect())
        .collect();
    let width = cells
        .iter()
        .flatten()
        .chain(columns)
        .map(|s| s.chars().count())
        .max()
        .unwrap_or(6);
    let mut s = format!(
        "harmonic mould, degree {} ({}, {} × {}): P_ij = Σ coefficient × boundary point; \
         rows sum to 1 within {:.1e}\n{:>7}",
        m.degree,
        m.form.name(),
        m.across,
        m.degree,
        m.row_sum_error,
        "P(i,j)"
    );
    let half = m.degree + 1;
    for (k, c) in columns.iter().enumerate() {
        s += if k == half { " |" } else { "" };
        s += &format!(" {c:>width$}");
    }
    for (r, row) in cells.iter().enumerate() {
        let (i, j) = m.inner_index(r);
        s += &format!("\n{:>7}", format!("({i},{j})"));
        for (k, c) in row.iter().enumerate() {
            s += if k == half { " |" } else { "" };
            s += &format!(" {c:>width$}");
        }
    }
    s
}

/// c to 6 decimals, with rounding noise below them shown as 0.000000, not
/// -0.000000.
fn six_places(c: f64) -> String {
    let s = format!("{c:.6}");
    if s == "-0.000000" {
        s[1..].to_string()
    } else {
        s
    }
}
