//! The `font` keys (`shape.font`, `shape.part[i].font`): the built-in
//! `paper`, a font file's path, or a family and style name looked up among
//! installed fonts.
//!
//! A value is a path when it ends in `.ttf`, `.otf`, `.ttc` or `.otc` (any
//! case), contains `/` or `\`, or is `.` or `..` ([`font_lookup::is_font_path`]); a relative
//! path is taken from the job file's directory. Any other value but `paper`
//! is a name (`DejaVu Sans Bold`), found by [`font_lookup::find_face`].

use super::{defaults, echo, invalid, JobError};
use crate::geometry::{font_lookup, glyphs, FontSource};
use std::path::Path;

/// Where a job's font names are looked up.
#[derive(Clone, Copy, Default)]
pub enum Fonts<'a> {
    /// The system's fonts ([`font_lookup::system_fonts`]), loaded the first
    /// time a job names a family.
    #[default]
    System,
    /// This database (tests pass the fonts of `tests/data`).
    Given(&'a fontdb::Database),
}

impl Fonts<'_> {
    fn database(&self) -> &fontdb::Database {
        match self {
            Fonts::System => font_lookup::system_fonts(),
            Fonts::Given(db) => db,
        }
    }
}

/// Where the files and fonts a job names are found.
#[derive(Clone, Copy)]
pub struct Sources<'a> {
    /// Relative paths are taken from here (the job file's directory).
    pub base_dir: &'a Path,
    /// Font names are looked up here.
    pub fonts: Fonts<'a>,
}

/// The font of `text` (`font_key` is where `font` was written, `text_key` where
/// the text was): `paper` must have every character (line breaks aside); a
/// file path must exist; a name must find a face.
pub(crate) fn resolve_font(
    font_key: &str,
    text_key: &str,
    font: Option<&str>,
    text: &str,
    src: &Sources<'_>,
) -> Result<FontSource, JobError> {
    match font.unwrap_or(defaults::FONT) {
        "paper" => {
            let have = glyphs::paper_chars();
            if let Some(ch) = text
                .chars()
                .find(|c| *c != ' ' && *c != '\n' && !have.contains(c))
            {
                let list: String = have.iter().collect();
                return Err(invalid(
                    text_key,
                    format!("has {ch:?}, but the font `paper` has no glyph for it (it has {list})"),
                ));
            }
            Ok(FontSource::Paper)
        }
        path if font_lookup::is_font_path(path) => font_file(font_key, src.base_dir.join(path)),
        name => {
            if name.trim().is_empty() {
                return Err(invalid(
                    font_key,
                    "must not be empty: give \"paper\", a font file's path or a family name",
                ));
            }
            if name.chars().count() > font_lookup::MAX_NAME_CHARS {
                return Err(invalid(
                    font_key,
                    format!(
                        "{} is longer than a family and style name (at most {} characters)",
                        echo::clip(name),
                        font_lookup::MAX_NAME_CHARS
                    ),
                ));
            }
            let found = font_lookup::find_face(src.fonts.database(), name)
                .map_err(|e| invalid(font_key, e.to_string()))?;
            Ok(FontSource::Found {
                name: name.to_string(),
                path: found.path,
                index: found.index,
            })
        }
    }
}

/// A font file's path, checked to be a regular file.
fn font_file(font_key: &str, p: std::path::PathBuf) -> Result<FontSource, JobError> {
    if p.is_dir() {
        return Err(invalid(
            font_key,
            format!(
                "is a directory, not a font file: {} (give a .ttf or .otf file)",
                p.display()
            ),
        ));
    }
    if p.exists() && !p.is_file() {
        return Err(invalid(
            font_key,
            format!(
                "is not a regular file: {} (give a .ttf or .otf file)",
                echo::clip(&p.display().to_string())
            ),
        ));
    }
    if !p.is_file() {
        return Err(JobError::FontNotFound {
            key: font_key.into(),
            path: p,
        });
    }
    Ok(FontSource::File(p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{font_lookup, ShapeSource};
    use crate::job::{parse_job_with, Job};

    fn data() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
    }

    /// A text job in `font`, its names looked up in the fonts of tests/data.
    fn job(font: &str) -> Result<Job, JobError> {
        let db = font_lookup::fonts_in(&data());
        let src = Sources {
            base_dir: &data(),
            fonts: Fonts::Given(&db),
        };
        let text = format!(
            "[shape]\ntext = \"AV\"\nfont = \"{font}\"\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n"
        );
        parse_job_with(&text, "t", &src)
    }

    fn font_of(j: &Job) -> FontSource {
        match &j.shape {
            ShapeSource::Text { font, .. } => font.clone(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_family_name_finds_its_file_and_a_path_stays_a_path() {
        for (name, file) in [
            ("DejaVu Sans", "DejaVuSans.ttf"),
            ("DejaVu Sans Bold", "DejaVuSans-Bold.ttf"),
            ("dejavu sans BOLD", "DejaVuSans-Bold.ttf"),
            ("DejaVu Serif Book", "DejaVuSerif.ttf"),
        ] {
            let f = font_of(&job(name).expect(name));
            let FontSource::Found {
                name: n,
                path,
                index,
            } = f
            else {
                panic!("{name}: {f:?}")
            };
            assert_eq!((n.as_str(), index), (name, 0));
            assert_eq!(path, data().join(file), "{name}");
        }
        let f = font_of(&job("DejaVuSans.ttf").expect("path"));
        assert_eq!(f, FontSource::File(data().join("DejaVuSans.ttf")));
        let e = job("paper").unwrap_err().to_string();
        assert!(
            e.starts_with("shape.text has 'V', but the font `paper`"),
            "{e}"
        );
    }

    #[test]
    fn a_name_not_found_names_the_key_and_close_families() {
        let e = job("DejaVu Sands Bold").unwrap_err().to_string();
        assert_eq!(
            e,
            "shape.font no font family \"DejaVu Sands Bold\" among the 3 installed faces; the closest family names: \"DejaVu Sans\", \"DejaVu Serif\""
        );
        let e = job("DejaVu Sans Italic").unwrap_err().to_string();
        assert_eq!(
            e,
            "shape.font the family \"DejaVu Sans\" has no Italic face (it has Regular, Bold)"
        );
        let e = job("DejaVu Sans Blod").unwrap_err().to_string();
        assert!(e.starts_with("shape.font \"DejaVu Sans Blod\": \"Blod\" is not a style word of the family \"DejaVu Sans\""), "{e}");
        assert!(e.ends_with("the family has Regular, Bold)"), "{e}");
        let e = job("DejaVu Sans Bold Black").unwrap_err().to_string();
        assert!(e.contains("\"Black\" is not a style word"), "{e}");
        let e = job("fonts/none.otf").unwrap_err().to_string();
        assert!(e.starts_with("shape.font: no such file:"), "{e}");
        let e = job("  ").unwrap_err().to_string();
        assert!(e.starts_with("shape.font must not be empty"), "{e}");
    }
}
