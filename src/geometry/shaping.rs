//! Text shaping: which glyphs a line of text becomes and where they go, by
//! rustybuzz (HarfBuzz's shaping algorithm in Rust).
//!
//! HarfBuzz's default features for the script are applied: `ccmp`, `locl`,
//! `rlig`, `liga`, `clig`, `calt` (ligatures and contextual forms from
//! GSUB), `kern` (GPOS pair kerning, or the legacy `kern` table when the font
//! has no GPOS kerning), `mark` and `mkmk` (combining marks attached by their
//! GPOS anchors). Unicode normalisation composes a base and a combining mark
//! into one glyph when the font has it (`e` + U+0301 is set as `é`).
//! The direction and script are guessed from the text (one direction per
//! line; no bidirectional reordering).

use super::{GeometryError, Vec2};

/// One glyph as the shaper placed it, in font units (y up).
#[derive(Clone, Debug, PartialEq)]
pub struct ShapedGlyph {
    /// The glyph index in the font.
    pub(crate) id: u16,
    /// Index (in characters, from 0) of the first character of the glyph's
    /// cluster in the line: a ligature, and a base with its marks, share one.
    pub(crate) cluster: usize,
    /// How far the pen moves after this glyph (0 for an attached mark).
    pub advance: f64,
    /// Where the glyph's origin is drawn relative to the pen.
    pub(crate) offset: Vec2,
}

/// Shapes `line` (no line breaks) with `face`. Whitespace the font has no
/// glyph for is set as a space. A character the font has no glyph for (the
/// shaper gives glyph 0, `.notdef`) is `MissingGlyph` naming it; `font` names
/// the font in that error.
pub fn shape_line(
    face: &rustybuzz::Face<'_>,
    font: &str,
    line: &str,
) -> Result<Vec<ShapedGlyph>, GeometryError> {
    let chars: Vec<char> = line
        .chars()
        .map(|c| {
            if c.is_whitespace() && face.glyph_index(c).is_none() {
                ' '
            } else {
                c
            }
        })
        .collect();
    let text: String = chars.iter().collect();
    // Byte offset of each character in `text`: the shaper's clusters are bytes.
    let starts: Vec<usize> = text.char_indices().map(|(b, _)| b).collect();
    let mut buffer = rustybuzz::UnicodeBuffer::new();
    buffer.push_str(&text);
    buffer.guess_segment_properties();
    let out = rustybuzz::shape(face, &[], buffer);
    let mut glyphs = Vec::with_capacity(out.len());
    for (info, pos) in out.glyph_infos().iter().zip(out.glyph_positions()) {
        let cluster = starts.partition_point(|&b| b < info.cluster as usize);
        let id = u16::try_from(info.glyph_id).unwrap_or(0);
        if id == 0 {
            check_blank(face, font, &chars, cluster, &starts, &out)?;
        }
        glyphs.push(ShapedGlyph {
            id,
            cluster,
            advance: f64::from(pos.x_advance),
            offset: Vec2::new(f64::from(pos.x_offset), f64::from(pos.y_offset)),
        });
    }
    Ok(glyphs)
}

/// `Ok` when the cluster at character `cluster` that came out as `.notdef` is
/// only whitespace (a font without even a space: nothing is drawn there);
/// else `MissingGlyph` for its first character the font lacks (or its first).
fn check_blank(
    face: &ttf_parser::Face<'_>,
    font: &str,
    chars: &[char],
    cluster: usize,
    starts: &[usize],
    out: &rustybuzz::GlyphBuffer,
) -> Result<(), GeometryError> {
    // The cluster runs to the next cluster start after it, or the line's end.
    let end = out
        .glyph_infos()
        .iter()
        .map(|g| starts.partition_point(|&b| b < g.cluster as usize))
        .filter(|&c| c > cluster)
        .min()
        .unwrap_or(chars.len());
    let members = chars.get(cluster..end).unwrap_or(&[]);
    if !members.is_empty() && members.iter().all(|c| c.is_whitespace()) {
        return Ok(());
    }
    let ch = members
        .iter()
        .find(|c| !c.is_whitespace() && face.glyph_index(**c).is_none())
        .or(members.first())
        .copied()
        .unwrap_or('\u{FFFD}');
    Err(GeometryError::MissingGlyph {
        font: font.to_string(),
        ch,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ttf_parser::gpos::{PairAdjustment, PositioningSubtable};
    use ttf_parser::gsub::SubstitutionSubtable;
    use ttf_parser::opentype_layout::LayoutTable;
    use ttf_parser::{GlyphId, Tag};

    fn data(file: &str) -> Vec<u8> {
        let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
        std::fs::read(path).expect("test font")
    }

    fn shaped(face: &rustybuzz::Face<'_>, s: &str) -> Vec<ShapedGlyph> {
        shape_line(face, "test", s).expect("shaped")
    }

    /// The lookups of `feature` for the Latin script's default language
    /// (else the DFLT script's), read from the table without the shaper.
    fn lookups(table: &LayoutTable<'_>, feature: &[u8; 4]) -> Vec<u16> {
        let script = table
            .scripts
            .find(Tag::from_bytes(b"latn"))
            .or_else(|| table.scripts.find(Tag::from_bytes(b"DFLT")))
            .expect("latn or DFLT script");
        let lang = script.default_language.expect("default language");
        let mut out = Vec::new();
        for fi in lang.feature_indices {
            let f = table.features.get(fi).expect("feature");
            if f.tag == Tag::from_bytes(feature) {
                out.extend(f.lookup_indices);
            }
        }
        out
    }

    /// The GPOS `kern` pair adjustment of the first glyph's advance for the
    /// pair (left, right), font units: in each kern lookup, the first pair
    /// subtable that covers the pair, summed over lookups.
    fn gpos_pair_kern(face: &ttf_parser::Face<'_>, left: GlyphId, right: GlyphId) -> i32 {
        let gpos = face.tables().gpos.expect("GPOS");
        let mut total = 0;
        for li in lookups(&gpos, b"kern") {
            let lookup = gpos.lookups.get(li).expect("lookup");
            for k in 0..lookup.subtables.len() {
                let Some(PositioningSubtable::Pair(pair)) = lookup.subtables.get(k) else {
                    continue;
                };
                let rec = match pair {
                    PairAdjustment::Format1 { coverage, sets } => coverage
                        .get(left)
                        .and_then(|i| sets.get(i))
                        .and_then(|set| set.get(right))
                        .map(|(a, _)| a),
                    PairAdjustment::Format2 {
                        coverage,
                        classes,
                        matrix,
                    } => coverage
                        .contains(left)
                        .then(|| matrix.get((classes.0.get(left), classes.1.get(right))))
                        .flatten()
                        .map(|(a, _)| a),
                };
                if let Some(a) = rec {
                    total += i32::from(a.x_advance);
                    break;
                }
            }
        }
        total
    }

    #[test]
    fn gpos_kerning_of_av_and_to_in_dejavu_sans() {
        let bytes = data("DejaVuSans.ttf");
        let face = rustybuzz::Face::from_slice(&bytes, 0).expect("face");
        let adv = |c: char| {
            let id = face.glyph_index(c).expect("glyph");
            (id, f64::from(face.glyph_hor_advance(id).expect("advance")))
        };
        for (pair, measured) in [("AV", -131), ("To", -348)] {
            let mut cs = pair.chars();
            let (l, r) = (cs.next().expect("l"), cs.next().expect("r"));
            let ((lid, ladv), (rid, radv)) = (adv(l), adv(r));
            let k = gpos_pair_kern(&face, lid, rid);
            // The figures docs/shapes.md gives, read from the table.
            assert_eq!(k, measured, "{pair}");
            let g = shaped(&face, pair);
            assert_eq!((g[0].id, g[1].id), (lid.0, rid.0), "{pair}");
            assert_eq!(g[0].advance, ladv + f64::from(k), "{pair}");
            assert_eq!(g[1].advance, radv, "{pair}");
            assert_eq!((g[0].cluster, g[1].cluster), (0, 1));
        }
    }

    /// The ligature GSUB's `liga` lookups make of `components`, read from
    /// the table.
    fn gsub_ligature(face: &ttf_parser::Face<'_>, components: &[GlyphId]) -> Option<u16> {
        let gsub = face.tables().gsub.expect("GSUB");
        for li in lookups(&gsub, b"liga") {
            let lookup = gsub.lookups.get(li).expect("lookup");
            for k in 0..lookup.subtables.len() {
                let Some(SubstitutionSubtable::Ligature(lig)) = lookup.subtables.get(k) else {
                    continue;
                };
                let Some(set) = lig
                    .coverage
                    .get(components[0])
                    .and_then(|i| lig.ligature_sets.get(i))
                else {
                    continue;
                };
                for l in set {
                    let rest: Vec<GlyphId> = l.components.into_iter().collect();
                    if rest == components[1..] {
                        return Some(l.glyph.0);
                    }
                }
            }
        }
        None
    }

    #[test]
    fn ligatures_of_dejavu_sans_and_serif() {
        // Both fonts have fi and ffi in their `liga` lookups; the shaper sets
        // DejaVu Serif's "ffi" as glyph 3314 and an i, so only fi is shaped
        // here for both.

        for (file, fi, ffi) in [
            ("DejaVuSans.ttf", 5042, Some(5044)),
            ("DejaVuSerif.ttf", 3315, Some(3317)),
        ] {
            let bytes = data(file);
            let face = rustybuzz::Face::from_slice(&bytes, 0).expect("face");
            let id = |c: char| face.glyph_index(c).expect("glyph");
            let (f, i) = (id('f'), id('i'));
            assert_eq!(gsub_ligature(&face, &[f, i]), Some(fi), "{file}");
            assert_eq!(gsub_ligature(&face, &[f, f, i]), ffi, "{file}");
            let g = shaped(&face, "fit");
            assert_eq!(g.len(), 2, "{file}: {g:?}");
            assert_eq!((g[0].id, g[0].cluster), (fi, 0), "{file}");
            // The ligature's own advance: the pen does not add f's and i's.
            let lig_adv = f64::from(face.glyph_hor_advance(GlyphId(fi)).expect("adv"));
            assert_eq!(g[0].advance, lig_adv, "{file}");
            assert_eq!((g[1].id, g[1].cluster), (id('t').0, 2), "{file}");
        }
    }

    /// The GPOS `mark` attachment of `mark` on `base`: (base anchor − mark
    /// anchor), font units, read from the table.
    fn gpos_mark_on_base(face: &ttf_parser::Face<'_>, base: GlyphId, mark: GlyphId) -> (i32, i32) {
        let gpos = face.tables().gpos.expect("GPOS");
        for li in lookups(&gpos, b"mark") {
            let lookup = gpos.lookups.get(li).expect("lookup");
            for k in 0..lookup.subtables.len() {
                let Some(PositioningSubtable::MarkToBase(mb)) = lookup.subtables.get(k) else {
                    continue;
                };
                let (Some(mi), Some(bi)) = (mb.mark_coverage.get(mark), mb.base_coverage.get(base))
                else {
                    continue;
                };
                let (class, ma) = mb.marks.get(mi).expect("mark record");
                let ba = mb.anchors.get(bi, class).expect("base anchor");
                return (
                    i32::from(ba.x) - i32::from(ma.x),
                    i32::from(ba.y) - i32::from(ma.y),
                );
            }
        }
        panic!("no mark-to-base attachment");
    }

    #[test]
    fn a_combining_mark_sits_on_its_base_by_the_gpos_anchors() {
        let bytes = data("DejaVuSans.ttf");
        let face = rustybuzz::Face::from_slice(&bytes, 0).expect("face");
        let id = |c: char| face.glyph_index(c).expect("glyph");
        // x has no precomposed x-acute: the mark is attached by GPOS.
        let g = shaped(&face, "x\u{301}");
        assert_eq!(g.len(), 2, "{g:?}");
        let (x, acute) = (id('x'), id('\u{301}'));
        assert_eq!((g[0].id, g[1].id), (x.0, acute.0));
        assert_eq!((g[0].cluster, g[1].cluster), (0, 0), "one cluster");
        assert_eq!(g[1].advance, 0.0);
        let (dx, dy) = gpos_mark_on_base(&face, x, acute);
        // The mark's origin relative to the base's: the pen has moved by the
        // base's advance, then the offset.
        let placed = Vec2::new(g[0].advance + g[1].offset.x, g[1].offset.y);
        assert_eq!(placed, Vec2::new(f64::from(dx), f64::from(dy)));
        // e + U+0301 is composed into é (the font has it), one glyph.
        let e = shaped(&face, "e\u{301}");
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].id, id('é').0);
    }

    #[test]
    fn missing_glyphs_and_whitespace() {
        let bytes = data("DejaVuSans.ttf");
        let face = rustybuzz::Face::from_slice(&bytes, 0).expect("face");
        match shape_line(&face, "DejaVuSans.ttf", "A\u{1D11E}B") {
            Err(GeometryError::MissingGlyph { font, ch }) => {
                assert_eq!((font.as_str(), ch), ("DejaVuSans.ttf", '\u{1D11E}'));
            }
            other => panic!("{other:?}"),
        }
        // A mark the font lacks is named, not its base.
        match shape_line(&face, "f", "x\u{1AB0}") {
            Err(GeometryError::MissingGlyph { ch, .. }) => assert_eq!(ch, '\u{1AB0}'),
            other => panic!("{other:?}"),
        }
        // A tab (no glyph in DejaVu) is set as a space.
        let space = face.glyph_index(' ').expect("space");
        let g = shaped(&face, "A\tB");
        assert_eq!(g[1].id, space.0);
        assert_eq!(g[1].cluster, 1);
        assert_eq!(
            g[1].advance,
            f64::from(face.glyph_hor_advance(space).expect("adv"))
        );
    }
}
