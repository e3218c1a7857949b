//! Finding a font by name (`font = "DejaVu Sans Bold"`) in a `fontdb`
//! database: the system's fonts for the command line, any database in tests.
//!
//! A name is a family followed by style words. The family is the longest
//! leading run of words that is a family in the database (compared without
//! regard to case; `fontdb` takes a face's typographic family, name ID 16,
//! else its family, name ID 1); the words after it are weight, slope and
//! width words ([`STYLE_WORDS`]), each kind at most once, defaulting to
//! Regular, upright, normal width. The face chosen has exactly that width, a
//! weight class that rounds to the asked one (to the nearest 100; of several,
//! the closest), and that slope (Italic and Oblique standing in for each
//! other when the family has only one of them).

#[cfg(test)]
use std::path::Path;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A face found by name.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FoundFace {
    /// The file that holds it.
    pub(crate) path: PathBuf,
    /// Its index in the file (a `.ttc` collection holds several).
    pub(crate) index: u32,
}

/// Why a name found no face.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum LookupError {
    /// The database is empty.
    #[error("no fonts were found on this system to look {name:?} up in; give the path of a .ttf or .otf file instead")]
    NoFonts {
        /// The name asked for.
        name: String,
    },
    /// No leading words of the name are a family.
    #[error(
        "no font family {name:?} among the {faces} installed faces; the closest family names: {}",
        quoted(close)
    )]
    NoFamily {
        /// The name asked for.
        name: String,
        /// How many faces were searched.
        faces: usize,
        /// The families most like the name, closest first.
        close: Vec<String>,
    },
    /// The family is there but a word after it is not a style word.
    #[error("{name:?}: {word:?} is not a style word of the family {family:?} (style words: {}; the family has {})", STYLE_WORDS.join(", "), have.join(", "))]
    UnknownWord {
        /// The name asked for.
        name: String,
        /// The family found.
        family: String,
        /// The word not understood.
        word: String,
        /// The family's faces, as style words.
        have: Vec<String>,
    },
    /// The family has no face of that style.
    #[error("the family {family:?} has no {want} face (it has {})", have.join(", "))]
    NoStyle {
        /// The family found.
        family: String,
        /// The style asked for, in words.
        want: String,
        /// The family's faces, as style words.
        have: Vec<String>,
    },
    /// The name is longer than any family and style name.
    #[error("is {chars} characters long; a family and style name has at most {MAX_NAME_CHARS}")]
    TooLong {
        /// Its length, characters.
        chars: usize,
    },
    /// The face is in memory, not a file (a database built from bytes).
    #[error("the face {name:?} was not loaded from a file")]
    NotAFile {
        /// The name asked for.
        name: String,
    },
}

fn quoted(names: &[String]) -> String {
    let q: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    q.join(", ")
}

/// Whether a `font` value is a file path rather than a family name: it ends
/// in `.ttf`, `.otf`, `.ttc` or `.otc` (any case), contains `/` or `\`, or
/// is `.` or `..`.
pub(crate) fn is_font_path(value: &str) -> bool {
    let lower = value.to_ascii_lowercase();
    value == "."
        || value == ".."
        || value.contains('/')
        || value.contains('\\')
        || [".ttf", ".otf", ".ttc", ".otc"]
            .iter()
            .any(|ext| lower.ends_with(ext))
}

/// The system's fonts (`fontdb`'s `load_system_fonts`: fontconfig's
/// directories on Linux, the standard font folders elsewhere), loaded the
/// first time a job names a family.
pub(crate) fn system_fonts() -> &'static fontdb::Database {
    static DB: OnceLock<fontdb::Database> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = fontdb::Database::new();
        db.load_system_fonts();
        db
    })
}

/// The fonts in one directory (and its subdirectories), for tests.
#[cfg(test)]
pub(crate) fn fonts_in(dir: &Path) -> fontdb::Database {
    let mut db = fontdb::Database::new();
    db.load_fonts_dir(dir);
    db
}

/// Weight, slope and width words, as written in errors. Matching ignores
/// case and hyphens; `Normal`, `Book` and `Roman` also mean Regular,
/// `Hairline` Thin, `UltraLight` ExtraLight, `DemiBold` SemiBold,
/// `UltraBold` ExtraBold and `Heavy` Black; two words written apart
/// (`Semi Bold`) are read as one.
pub(crate) const STYLE_WORDS: &[&str] = &[
    "Thin",
    "ExtraLight",
    "Light",
    "Regular",
    "Medium",
    "SemiBold",
    "Bold",
    "ExtraBold",
    "Black",
    "Italic",
    "Oblique",
    "UltraCondensed",
    "ExtraCondensed",
    "Condensed",
    "SemiCondensed",
    "SemiExpanded",
    "Expanded",
    "ExtraExpanded",
    "UltraExpanded",
];

/// A requested or available style.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Style {
    /// Weight class rounded to a multiple of 100.
    weight: u16,
    slope: fontdb::Style,
    stretch: fontdb::Stretch,
}

impl Style {
    const REGULAR: Style = Style {
        weight: 400,
        slope: fontdb::Style::Normal,
        stretch: fontdb::Stretch::Normal,
    };

    fn of(face: &fontdb::FaceInfo) -> Style {
        Style {
            weight: round_weight(face.weight.0),
            slope: face.style,
            stretch: face.stretch,
        }
    }

    /// In style words: `Bold Oblique`, `Condensed`, `Regular`.
    fn words(&self) -> String {
        let mut w: Vec<&str> = Vec::new();
        if let Some((_, s)) = STRETCHES.iter().find(|(s, _)| *s == self.stretch) {
            w.push(s);
        }
        let weight = WEIGHTS.iter().find(|(v, _)| *v == self.weight);
        match weight {
            Some((400, _)) if !w.is_empty() || self.slope != fontdb::Style::Normal => {}
            Some((_, name)) => w.push(name),
            None => return format!("weight {}", self.weight),
        }
        match self.slope {
            fontdb::Style::Italic => w.push("Italic"),
            fontdb::Style::Oblique => w.push("Oblique"),
            fontdb::Style::Normal => {}
        }
        w.join(" ")
    }
}

/// A weight class to the nearest multiple of 100, within 100..=900.
fn round_weight(w: u16) -> u16 {
    ((w.saturating_add(50) / 100) * 100).clamp(100, 900)
}

const WEIGHTS: &[(u16, &str)] = &[
    (100, "Thin"),
    (200, "ExtraLight"),
    (300, "Light"),
    (400, "Regular"),
    (500, "Medium"),
    (600, "SemiBold"),
    (700, "Bold"),
    (800, "ExtraBold"),
    (900, "Black"),
];

const STRETCHES: &[(fontdb::Stretch, &str)] = &[
    (fontdb::Stretch::UltraCondensed, "UltraCondensed"),
    (fontdb::Stretch::ExtraCondensed, "ExtraCondensed"),
    (fontdb::Stretch::Condensed, "Condensed"),
    (fontdb::Stretch::SemiCondensed, "SemiCondensed"),
    (fontdb::Stretch::SemiExpanded, "SemiExpanded"),
    (fontdb::Stretch::Expanded, "Expanded"),
    (fontdb::Stretch::ExtraExpanded, "ExtraExpanded"),
    (fontdb::Stretch::UltraExpanded, "UltraExpanded"),
];

/// What one style word sets.
enum Word {
    Weight(u16),
    Slope(fontdb::Style),
    Stretch(fontdb::Stretch),
}

/// A style word (lower case, hyphens removed) and what it sets.
fn style_word(w: &str) -> Option<Word> {
    let weight = match w {
        "normal" | "book" | "roman" => Some(400),
        "hairline" => Some(100),
        "ultralight" => Some(200),
        "demibold" => Some(600),
        "ultrabold" => Some(800),
        "heavy" => Some(900),
        _ => WEIGHTS
            .iter()
            .find(|(_, n)| n.to_ascii_lowercase() == w)
            .map(|(v, _)| *v),
    };
    if let Some(v) = weight {
        return Some(Word::Weight(v));
    }
    match w {
        "italic" => return Some(Word::Slope(fontdb::Style::Italic)),
        "oblique" => return Some(Word::Slope(fontdb::Style::Oblique)),
        _ => {}
    }
    STRETCHES
        .iter()
        .find(|(_, n)| n.to_ascii_lowercase() == w)
        .map(|(s, _)| Word::Stretch(*s))
}

/// The style that `words` ask for, or the first word (as written) that is not
/// a style word or repeats a kind already given.
fn parse_style<'a>(words: &[&'a str]) -> Result<Style, &'a str> {
    let mut style = Style::REGULAR;
    let mut seen = [false; 3];
    let norm = |w: &str| w.to_lowercase().replace('-', "");
    let mut i = 0;
    while i < words.len() {
        // Two words written apart (`Semi Bold`) count as one when joined.
        let pair = words
            .get(i + 1)
            .and_then(|next| style_word(&(norm(words[i]) + &norm(next))));
        let (word, used) = match pair {
            Some(w) => (w, 2),
            None => (style_word(&norm(words[i])).ok_or(words[i])?, 1),
        };
        let kind = match word {
            Word::Weight(v) => {
                style.weight = v;
                0
            }
            Word::Slope(s) => {
                style.slope = s;
                1
            }
            Word::Stretch(s) => {
                style.stretch = s;
                2
            }
        };
        if std::mem::replace(&mut seen[kind], true) {
            return Err(words[i]);
        }
        i += used;
    }
    Ok(style)
}

/// Whether `face` belongs to `family` (any of its names, any case).
fn in_family(face: &fontdb::FaceInfo, family: &str) -> bool {
    face.families
        .iter()
        .any(|(f, _)| f.to_lowercase() == family.to_lowercase())
}

/// Longest name looked up, characters: the search tries every leading run of
/// words against every face, so its work grows as the square of the words.
pub(crate) const MAX_NAME_CHARS: usize = 200;

/// The face of `db` that `name` means (see the module's rules).
pub(crate) fn find_face(db: &fontdb::Database, name: &str) -> Result<FoundFace, LookupError> {
    let chars = name.chars().count();
    if chars > MAX_NAME_CHARS {
        return Err(LookupError::TooLong { chars });
    }
    if db.is_empty() {
        return Err(LookupError::NoFonts { name: name.into() });
    }
    let words: Vec<&str> = name.split_whitespace().collect();
    let split = (1..=words.len()).rev().find_map(|k| {
        let family = words[..k].join(" ");
        db.faces()
            .find(|f| in_family(f, &family))
            .map(|f| (k, family_name(f, &family)))
    });
    let Some((k, family)) = split else {
        return Err(LookupError::NoFamily {
            name: name.into(),
            faces: db.len(),
            close: close_families(db, &words),
        });
    };
    let faces: Vec<&fontdb::FaceInfo> = db.faces().filter(|f| in_family(f, &family)).collect();
    let have = || styles_of(&faces);
    let want = parse_style(&words[k..]).map_err(|word| LookupError::UnknownWord {
        name: name.into(),
        family: family.clone(),
        word: word.into(),
        have: have(),
    })?;
    // Italic and Oblique stand in for each other when the family has only
    // one of them (fontdb reads the slope from OS/2 fsSelection, where many
    // fonts mark their oblique faces italic).
    let other = match want.slope {
        fontdb::Style::Italic => fontdb::Style::Oblique,
        fontdb::Style::Oblique => fontdb::Style::Italic,
        fontdb::Style::Normal => fontdb::Style::Normal,
    };
    let pick = |slope| {
        faces
            .iter()
            .filter(|f| Style::of(f) == Style { slope, ..want })
            .min_by_key(|f| f.weight.0.abs_diff(want.weight))
    };
    let Some(face) = pick(want.slope).or_else(|| pick(other)) else {
        return Err(LookupError::NoStyle {
            family,
            want: want.words(),
            have: have(),
        });
    };
    match &face.source {
        fontdb::Source::File(path) | fontdb::Source::SharedFile(path, _) => Ok(FoundFace {
            path: path.clone(),
            index: face.index,
        }),
        fontdb::Source::Binary(_) => Err(LookupError::NotAFile { name: name.into() }),
    }
}

/// The family's name as the font spells it (`asked` matched it, any case).
fn family_name(face: &fontdb::FaceInfo, asked: &str) -> String {
    face.families
        .iter()
        .find(|(f, _)| f.to_lowercase() == asked.to_lowercase())
        .map_or_else(|| asked.to_string(), |(f, _)| f.clone())
}

/// The distinct styles of `faces`, in words, sorted by weight then name.
fn styles_of(faces: &[&fontdb::FaceInfo]) -> Vec<String> {
    let mut styles: Vec<Style> = faces.iter().map(|f| Style::of(f)).collect();
    styles.sort_by_key(|s| {
        (
            s.stretch.to_number(),
            s.weight,
            s.slope != fontdb::Style::Normal,
        )
    });
    styles.dedup();
    styles.iter().map(Style::words).collect()
}

/// How many close family names an error lists.
pub(crate) const CLOSE_FAMILIES: usize = 5;

/// The [`CLOSE_FAMILIES`] families of `db` most like the name: each family is
/// scored by the best Jaro–Winkler similarity (lower case) between it and a
/// leading run of the name's words, so style words after a misspelt family
/// do not hide it.
fn close_families(db: &fontdb::Database, words: &[&str]) -> Vec<String> {
    let mut families: Vec<&str> = db
        .faces()
        .flat_map(|f| f.families.first().map(|(n, _)| n.as_str()))
        .collect();
    families.sort_unstable();
    families.dedup();
    let prefixes: Vec<String> = (1..=words.len())
        .map(|k| words[..k].join(" ").to_lowercase())
        .collect();
    let score = |fam: &str| {
        let fam = fam.to_lowercase();
        prefixes
            .iter()
            .map(|p| strsim::jaro_winkler(p, &fam))
            .fold(0.0, f64::max)
    };
    let mut scored: Vec<(f64, &str)> = families.iter().map(|f| (score(f), *f)).collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(b.1)));
    scored
        .into_iter()
        .take(CLOSE_FAMILIES)
        .map(|(_, f)| f.to_string())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn db() -> fontdb::Database {
        fonts_in(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data"))
    }

    #[test]
    fn paths_and_names_are_told_apart() {
        for p in [
            "a.ttf",
            "A.OTF",
            "x.ttc",
            "y.otc",
            "fonts/Foo",
            "C:\\Fonts\\foo",
            "./DejaVu",
        ] {
            assert!(is_font_path(p), "{p}");
        }
        for n in ["DejaVu Sans", "DejaVu Sans Bold", "Arial.Narrow", "paper"] {
            assert!(!is_font_path(n), "{n}");
        }
    }

    #[test]
    fn style_words() {
        let s = parse_style(&["Semi", "bold", "Condensed", "italic"]).expect("style");
        assert_eq!(s.weight, 600);
        assert_eq!(
            (s.slope, s.stretch),
            (fontdb::Style::Italic, fontdb::Stretch::Condensed)
        );
        assert_eq!(s.words(), "Condensed SemiBold Italic");
        assert_eq!(parse_style(&[]).expect("regular"), Style::REGULAR);
        assert_eq!(parse_style(&["Extra-Light"]).expect("200").weight, 200);
        assert_eq!(parse_style(&["Bold", "Heavy"]), Err("Heavy"));
        assert_eq!(parse_style(&["Wide"]), Err("Wide"));
        assert_eq!(
            (round_weight(350), round_weight(349), round_weight(0)),
            (400, 300, 100)
        );
        assert_eq!(round_weight(1000), 900);
    }

    /// A face record as fontdb would read it from a file at `path`.
    fn face(family: &str, path: &str, weight: u16, style: fontdb::Style) -> fontdb::FaceInfo {
        fontdb::FaceInfo {
            id: fontdb::ID::dummy(),
            source: fontdb::Source::File(path.into()),
            index: 0,
            families: vec![(family.into(), fontdb::Language::English_UnitedStates)],
            post_script_name: String::new(),
            style,
            weight: fontdb::Weight(weight),
            stretch: fontdb::Stretch::Normal,
            monospaced: false,
        }
    }

    #[test]
    fn italic_and_oblique_stand_in_for_each_other_only_when_needed() {
        use fontdb::Style::{Italic, Normal, Oblique};
        let mut db = fontdb::Database::new();
        db.push_face_info(face("Test Sans", "/f/Sans.ttf", 400, Normal));
        db.push_face_info(face("Test Sans", "/f/Sans-BoldOblique.ttf", 700, Italic));
        db.push_face_info(face("Test Sans", "/f/Sans-Book.ttf", 380, Normal));
        db.push_face_info(face("Test Serif", "/f/Serif-Italic.ttf", 400, Italic));
        db.push_face_info(face("Test Serif", "/f/Serif-Oblique.ttf", 400, Oblique));
        let path = |name: &str| find_face(&db, name).map(|f| f.path);
        assert_eq!(
            path("Test Sans Bold Oblique"),
            Ok("/f/Sans-BoldOblique.ttf".into())
        );
        assert_eq!(
            path("Test Sans Bold Italic"),
            Ok("/f/Sans-BoldOblique.ttf".into())
        );
        assert_eq!(
            path("Test Serif Oblique"),
            Ok("/f/Serif-Oblique.ttf".into())
        );
        assert_eq!(path("Test Serif Italic"), Ok("/f/Serif-Italic.ttf".into()));
        // Weight 380 rounds to 400 too; the exact 400 is closer.
        assert_eq!(path("Test Sans"), Ok("/f/Sans.ttf".into()));
        // No upright face stands in for a slanted one, nor the reverse.
        assert!(matches!(
            find_face(&db, "Test Sans Italic"),
            Err(LookupError::NoStyle { want, have, .. })
                if want == "Italic" && have == ["Regular", "Bold Italic"]
        ));
        assert!(matches!(
            find_face(&db, "Test Serif Bold"),
            Err(LookupError::NoStyle { .. })
        ));
    }

    #[test]
    fn lookups_in_the_test_fonts() {
        let db = db();
        assert_eq!(db.len(), 3, "DejaVuSans, DejaVuSans-Bold, DejaVuSerif");
        let bold = find_face(&db, "DejaVu Sans Bold").expect("bold");
        assert!(bold.path.ends_with("DejaVuSans-Bold.ttf"));
        assert_eq!(bold.index, 0);
        // A family name is the longest run of words that is one: "DejaVu
        // Serif" is not "DejaVu" + a style word.
        assert!(find_face(&db, "DejaVu Serif")
            .expect("serif")
            .path
            .ends_with("DejaVuSerif.ttf"));
        match find_face(&db, "Dejavu Sanz") {
            Err(LookupError::NoFamily { close, faces, .. }) => {
                assert_eq!(faces, 3);
                assert_eq!(close, ["DejaVu Sans", "DejaVu Serif"]);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            find_face(&fontdb::Database::new(), "DejaVu Sans"),
            Err(LookupError::NoFonts {
                name: "DejaVu Sans".into()
            })
        );
        // A database built from bytes has no file to give.
        let mut mem = fontdb::Database::new();
        let bytes =
            std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/DejaVuSerif.ttf"))
                .expect("font");
        mem.load_font_data(bytes);
        assert!(matches!(
            find_face(&mem, "DejaVu Serif"),
            Err(LookupError::NotAFile { .. })
        ));
    }
}
