//! G-code tokenizer and GRBL 1.1 modal-state tracker.
//!
//! Three layers, each usable alone:
//! - [`clean_line`]: what a sender puts on the wire: comments (`(...)`, `;...`) and
//!   whitespace removed, letters upper-cased, a `%` program delimiter dropped.
//! - [`tokenize`]: a cleaned block split into [`Word`]s (`G1`, `X10.5`, ...), with
//!   GRBL's error code for a malformed block (1: a value without a letter,
//!   2: a letter without a valid number).
//! - [`ModalState::execute`]: runs one block through the modal state GRBL keeps
//!   (motion mode, units, distance mode, plane, feed, spindle, coolant, work
//!   coordinate system, program position), rejecting what GRBL 1.1 rejects with
//!   GRBL's own error number (20 unsupported command, 21 modal group violation,
//!   22 undefined feed, 25 repeated word, ...).
//!
//! [`Program`] ties them together with file line numbers; the streamer uses it for
//! `--from-line` and the emulator in the tests uses it to answer `error:N`.

/// One G-code word: a letter and its number (`X-1.5` → `('X', -1.5)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Word {
    /// Upper-case letter.
    pub(crate) letter: char,
    /// The number after it.
    pub(crate) value: f64,
}

/// A block GRBL would reject, with GRBL 1.1's error number for it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("error {code}: {detail}")]
pub struct BlockError {
    /// GRBL 1.1 error number (`error:N`).
    pub code: u8,
    /// What in the block is wrong, in pfcam's words.
    pub(crate) detail: String,
}

impl BlockError {
    fn new(code: u8, detail: impl Into<String>) -> Self {
        BlockError {
            code,
            detail: detail.into(),
        }
    }
}

/// A [`BlockError`] located in a file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}: `{text}`: {error}")]
pub struct LineError {
    /// 1-based line number in the file.
    pub(crate) line: usize,
    /// The cleaned block.
    pub(crate) text: String,
    /// What GRBL would say.
    pub(crate) error: BlockError,
}

/// Strips comments and whitespace and upper-cases, as a sender does before sending.
///
/// `(...)` comments and everything after `;` are removed; an unclosed `(` comments
/// out the rest of the line. A line holding only `%` becomes empty. Like GRBL's
/// serial reader, control characters and the block-delete `/` are dropped too
/// (GRBL ignores `/`: the block runs; see [`has_block_delete`]).
pub(crate) fn clean_line(raw: &str) -> String {
    let mut out = String::with_capacity(raw.len());
    let mut in_paren = false;
    for c in raw.chars() {
        if in_paren {
            if c == ')' {
                in_paren = false;
            }
            continue;
        }
        match c {
            '(' => in_paren = true,
            ';' => break,
            '/' => {}
            c if c.is_whitespace() || c.is_control() => {}
            c => out.push(c.to_ascii_uppercase()),
        }
    }
    if out == "%" {
        out.clear();
    }
    out
}

/// Whether `raw` has a `/` outside comments: a block-delete mark, which GRBL
/// ignores (the block runs anyway).
pub(crate) fn has_block_delete(raw: &str) -> bool {
    let mut in_paren = false;
    for c in raw.chars() {
        match c {
            ')' if in_paren => in_paren = false,
            _ if in_paren => {}
            '(' => in_paren = true,
            ';' => return false,
            '/' => return true,
            _ => {}
        }
    }
    false
}

/// Splits a cleaned block (see [`clean_line`]) into words.
///
/// Errors: 1 when a character that is not a letter starts a word, 2 when a letter
/// is not followed by a valid number.
pub(crate) fn tokenize(block: &str) -> Result<Vec<Word>, BlockError> {
    let bytes = block.as_bytes();
    let mut words = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i] as char;
        if !c.is_ascii_alphabetic() {
            return Err(BlockError::new(
                1,
                format!("`{c}` where a word letter was expected"),
            ));
        }
        let letter = c.to_ascii_uppercase();
        i += 1;
        let start = i;
        if i < bytes.len() && (bytes[i] == b'-' || bytes[i] == b'+') {
            i += 1;
        }
        let mut digits = 0;
        let mut dots = 0;
        while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
            if bytes[i] == b'.' {
                dots += 1;
            } else {
                digits += 1;
            }
            i += 1;
        }
        if digits == 0 || dots > 1 {
            return Err(BlockError::new(
                2,
                format!("`{letter}` has no valid number after it"),
            ));
        }
        let text = &block[start..i];
        let value: f64 = text
            .parse()
            .map_err(|_| BlockError::new(2, format!("`{letter}{text}` is not a number")))?;
        words.push(Word { letter, value });
    }
    Ok(words)
}

/// G0/G1/G2/G3/G38.x/G80.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// G0.
    Rapid,
    /// G1.
    Linear,
    /// G2.
    ArcCw,
    /// G3.
    ArcCcw,
    /// G38.2 – G38.5 (the number ×10, e.g. 382).
    Probe(u16),
    /// G80: motion cancelled.
    None,
}

/// G20/G21.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// G20.
    Inch,
    /// G21.
    Mm,
}

/// G90/G91.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    /// G90.
    Absolute,
    /// G91.
    Incremental,
}

/// G17/G18/G19.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    /// G17.
    XY,
    /// G18.
    ZX,
    /// G19.
    YZ,
}

/// M3/M4/M5.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    /// M5.
    Off,
    /// M3.
    Cw,
    /// M4.
    Ccw,
}

/// G93/G94.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FeedMode {
    /// G93.
    InverseTime,
    /// G94.
    UnitsPerMinute,
}

/// The modal state GRBL 1.1 keeps between blocks, plus the program position.
///
/// Starts as GRBL does after reset: G0 G54 G17 G21 G90 G94 M5 M9, feed undefined.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalState {
    /// Motion mode.
    pub motion: Motion,
    /// Units of the numbers in the program.
    pub units: Units,
    /// Distance mode.
    pub distance: Distance,
    /// Arc plane.
    pub plane: Plane,
    /// Feed-rate mode.
    pub(crate) feed_mode: FeedMode,
    /// Work coordinate system, 54 ..= 59.
    pub wcs: u8,
    /// Feed rate in **mm/min** (GRBL converts F when it reads it, so a later
    /// G20/G21 does not change it), `None` until set.
    pub feed: Option<f64>,
    /// Spindle speed S (rpm), 0 until set.
    pub spindle_speed: f64,
    /// Spindle state.
    pub spindle: Spindle,
    /// M7 mist coolant.
    pub mist: bool,
    /// M8 flood coolant.
    pub flood: bool,
    /// Tool number T.
    pub(crate) tool: u32,
    /// Work position X, Y, Z in **mm**, `None` while unknown (before the first
    /// absolute move on that axis, after G28/G30/G53/G10).
    pub position: [Option<f64>; 3],
    /// M2/M30 seen.
    pub ended: bool,
}

impl Default for ModalState {
    fn default() -> Self {
        ModalState {
            motion: Motion::Rapid,
            units: Units::Mm,
            distance: Distance::Absolute,
            plane: Plane::XY,
            feed_mode: FeedMode::UnitsPerMinute,
            wcs: 54,
            feed: None,
            spindle_speed: 0.0,
            spindle: Spindle::Off,
            mist: false,
            flood: false,
            tool: 0,
            position: [None; 3],
            ended: false,
        }
    }
}

/// Modal groups of GRBL 1.1 (for the "two words of one group" check, error 21).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Group {
    NonModal,
    Motion,
    Plane,
    Distance,
    ArcDistance,
    FeedMode,
    Units,
    CutterComp,
    ToolLength,
    Wcs,
    PathControl,
    Stop,
    Spindle,
    Coolant,
    Override,
}

/// G code ×10 (G38.2 → 382) to its group; `None` = unsupported (error 20).
fn g_group(code10: u32) -> Option<Group> {
    Some(match code10 {
        40 | 100 | 280 | 281 | 300 | 301 | 530 | 920 | 921 => Group::NonModal,
        0 | 10 | 20 | 30 | 382 | 383 | 384 | 385 | 800 => Group::Motion,
        170 | 180 | 190 => Group::Plane,
        900 | 910 => Group::Distance,
        911 => Group::ArcDistance,
        930 | 940 => Group::FeedMode,
        200 | 210 => Group::Units,
        400 => Group::CutterComp,
        431 | 490 => Group::ToolLength,
        540 | 550 | 560 | 570 | 580 | 590 => Group::Wcs,
        610 => Group::PathControl,
        _ => return None,
    })
}

fn m_group(code: u32) -> Option<Group> {
    Some(match code {
        0 | 1 | 2 | 30 => Group::Stop,
        3..=5 => Group::Spindle,
        7..=9 => Group::Coolant,
        56 => Group::Override,
        _ => return None,
    })
}

/// The motion mode of a motion-group G code ×10.
fn motion_mode(code10: u32) -> Motion {
    match code10 {
        0 => Motion::Rapid,
        10 => Motion::Linear,
        20 => Motion::ArcCw,
        30 => Motion::ArcCcw,
        800 => Motion::None,
        p => Motion::Probe(p as u16),
    }
}

/// A block's words sorted by kind, with GRBL's checks on the words alone
/// (errors 20, 21, 23, 24, 25 and 4) done.
struct BlockWords {
    /// G codes ×10 (G38.2 → 382), in block order.
    gcodes: Vec<u32>,
    /// M codes, in block order.
    mcodes: Vec<u32>,
    /// The value of each other letter, indexed from `A`.
    values: [Option<f64>; 26],
}

impl BlockWords {
    /// Sorts and checks a tokenized block's words.
    fn collect(words: &[Word]) -> Result<Self, BlockError> {
        let mut b = BlockWords {
            gcodes: Vec::new(),
            mcodes: Vec::new(),
            values: [None; 26],
        };
        let mut groups: Vec<Group> = Vec::new();
        // G10/G28/G30/G92, G0–G3/G38.x and G43.1/G49 each claim the axis words; GRBL
        // allows one of them per block (error 24).
        let mut axis_command = false;
        for w in words {
            match w.letter {
                'G' => {
                    let code10 = g_code10(w.value)?;
                    let group = g_word_group(code10)?;
                    if matches!(
                        code10,
                        0 | 10 | 20 | 30 | 100 | 280 | 300 | 382..=385 | 431 | 490 | 920
                    ) {
                        if axis_command {
                            return Err(BlockError::new(
                                24,
                                format!(
                                    "G{}{} and another command in the block both use the axis words",
                                    code10 / 10,
                                    frac(code10)
                                ),
                            ));
                        }
                        axis_command = true;
                    }
                    // Non-modal commands (G4, G10, G28, G30, G53, G92) are one group too.
                    if groups.contains(&group) {
                        return Err(BlockError::new(
                            21,
                            format!(
                                "two G-codes of one modal group (G{}{})",
                                code10 / 10,
                                frac(code10)
                            ),
                        ));
                    }
                    groups.push(group);
                    b.gcodes.push(code10);
                }
                'M' => {
                    let (code, group) = m_word(w.value)?;
                    // M7 and M8 are one group: GRBL takes them on separate lines.
                    if groups.contains(&group) {
                        return Err(BlockError::new(
                            21,
                            format!("two M-codes of one modal group (M{code})"),
                        ));
                    }
                    groups.push(group);
                    b.mcodes.push(code);
                }
                'F' | 'I' | 'J' | 'K' | 'L' | 'N' | 'P' | 'R' | 'S' | 'T' | 'X' | 'Y' | 'Z' => {
                    b.set_value(w)?;
                }
                other => {
                    return Err(BlockError::new(
                        20,
                        format!("`{other}` is not a word GRBL knows"),
                    ))
                }
            }
        }
        Ok(b)
    }

    /// Stores a value word: once a block (error 25), and F, N, P, S and T
    /// not negative (error 4).
    fn set_value(&mut self, w: &Word) -> Result<(), BlockError> {
        let slot = &mut self.values[(w.letter as u8 - b'A') as usize];
        if slot.is_some() {
            return Err(BlockError::new(25, format!("`{}` appears twice", w.letter)));
        }
        if w.value < 0.0 && matches!(w.letter, 'F' | 'N' | 'P' | 'S' | 'T') {
            return Err(BlockError::new(
                4,
                format!("`{}` must not be negative", w.letter),
            ));
        }
        *slot = Some(w.value);
        Ok(())
    }

    /// The value of letter `c` (upper case, `A` to `Z`), if the block has it.
    fn v(&self, c: char) -> Option<f64> {
        self.values[(c as u8 - b'A') as usize]
    }

    /// The block's G code of `group`, if any (at most one, by error 21).
    fn code_of(&self, group: Group) -> Option<u32> {
        self.gcodes
            .iter()
            .copied()
            .find(|g| g_group(*g) == Some(group))
    }

    /// GRBL's checks that the words a command needs are there and no others
    /// (errors 26, 36, 27), given the block's non-modal command and whether
    /// it has axis words.
    fn check_word_use(&self, non_modal: Option<u32>, has_axes: bool) -> Result<(), BlockError> {
        let explicit_motion = self
            .gcodes
            .iter()
            .any(|g| g_group(*g) == Some(Group::Motion) && !matches!(g, 0 | 10 | 800));
        if explicit_motion && !has_axes && non_modal.is_none() {
            return Err(BlockError::new(26, "G2/G3/G38.x without axis words"));
        }
        if self.v('P').is_some() && !matches!(non_modal, Some(40) | Some(100)) {
            return Err(BlockError::new(36, "P word without G4 or G10"));
        }
        if self.v('L').is_some() && non_modal != Some(100) {
            return Err(BlockError::new(36, "L word without G10"));
        }
        if let Some(n) = self.v('N') {
            if n.fract() != 0.0 || n > 9_999_999.0 {
                return Err(BlockError::new(
                    27,
                    "line number N must be an integer up to 9999999",
                ));
            }
        }
        Ok(())
    }
}

/// A G word's number ×10 (G38.2 → 382), rejected as GRBL does: a negative
/// or finer number is not a G-code (20); a decimal on a G-code that has none
/// in GRBL is 23 (on one that has, G28.x, G38.x, G43.x, G61.x, G90.x, G92.x,
/// the unknown variants are left to [`g_word_group`]).
fn g_code10(value: f64) -> Result<u32, BlockError> {
    let code10 = (value * 10.0).round();
    if value < 0.0 || (value * 10.0 - code10).abs() > 1e-6 {
        return Err(BlockError::new(20, format!("G{value} is not a G-code")));
    }
    let code10 = code10 as u32;
    if code10 % 10 != 0
        && matches!(
            code10 / 10,
            0..=4 | 10 | 17..=21 | 40 | 53..=58 | 80 | 93 | 94
        )
    {
        return Err(BlockError::new(
            23,
            format!(
                "G{}{}: GRBL has no such variant of G{}",
                code10 / 10,
                frac(code10),
                code10 / 10
            ),
        ));
    }
    Ok(code10)
}

/// The modal group of a G code ×10, or GRBL's error for one it does not
/// support (29 for G59.x, else 20), saying why where that is known.
fn g_word_group(code10: u32) -> Result<Group, BlockError> {
    g_group(code10).ok_or_else(|| {
        let what = match code10 {
            410 | 420 | 411 | 421 => " (cutter compensation is not in GRBL)",
            430 => " (GRBL has only G43.1, the dynamic tool length offset)",
            810..=890 => " (canned cycles are not in GRBL)",
            591..=599 => " (G59.x is not in GRBL)",
            _ => "",
        };
        BlockError::new(
            if (591..=599).contains(&code10) {
                29
            } else {
                20
            },
            format!(
                "G{}{} is not supported by GRBL{what}",
                code10 / 10,
                frac(code10)
            ),
        )
    })
}

/// An M word's code and group, or GRBL's error: 20 for a negative or unknown
/// one, 23 for a fraction.
fn m_word(value: f64) -> Result<(u32, Group), BlockError> {
    if value < 0.0 {
        return Err(BlockError::new(20, format!("M{value} is not an M-code")));
    }
    if value.fract() != 0.0 {
        return Err(BlockError::new(
            23,
            format!("M{value}: M-codes take integers"),
        ));
    }
    let code = value as u32;
    let group = m_group(code)
        .ok_or_else(|| BlockError::new(20, format!("M{code} is not supported by GRBL")))?;
    Ok((code, group))
}

const MM_PER_INCH: f64 = 25.4;

impl ModalState {
    /// Runs one cleaned block (see [`clean_line`]) through the state, as GRBL's
    /// parser would. On error the state is left unchanged, like GRBL does.
    ///
    /// An empty block is accepted and changes nothing. `$` system commands are not
    /// G-code and are rejected with error 3 here; a sender handles them itself.
    pub fn execute(&mut self, block: &str) -> Result<(), BlockError> {
        if block.is_empty() {
            return Ok(());
        }
        if block.starts_with('$') {
            return Err(BlockError::new(3, "a `$` system command is not G-code"));
        }
        let words = tokenize(block)?;
        let mut next = self.clone();
        next.apply(&words)?;
        *self = next;
        Ok(())
    }

    /// Runs one tokenized block, GRBL's checks first and then its order of
    /// execution: feed mode, F, S, T, spindle, coolant, plane, units, distance,
    /// WCS, non-modal, motion, stop. The caller keeps the old state on error.
    fn apply(&mut self, words: &[Word]) -> Result<(), BlockError> {
        let b = BlockWords::collect(words)?;
        self.set_modes(&b)?;
        let non_modal = b.code_of(Group::NonModal);
        if let Some(m) = b.code_of(Group::Motion) {
            self.motion = motion_mode(m);
        }
        let axes = [b.v('X'), b.v('Y'), b.v('Z')];
        let has_axes = axes.iter().any(Option::is_some);
        b.check_word_use(non_modal, has_axes)?;
        let scale = if self.units == Units::Inch {
            MM_PER_INCH
        } else {
            1.0
        };
        if let Some(nm) = non_modal {
            if self.run_non_modal(nm, &b, &axes, scale)? {
                return Ok(());
            }
        }
        let tool_length = self.apply_tool_length(&b)?;
        if has_axes && !tool_length {
            self.check_feed(&b)?;
            if matches!(self.motion, Motion::ArcCw | Motion::ArcCcw) {
                self.check_arc(&b, &axes, scale)?;
            } else if ['I', 'J', 'K', 'R'].iter().any(|&c| b.v(c).is_some()) {
                return Err(BlockError::new(36, "I/J/K/R words without an arc"));
            }
            self.position = self.target(&axes, scale);
        } else if ['R', 'I', 'J', 'K'].iter().any(|&c| b.v(c).is_some()) {
            return Err(BlockError::new(36, "arc words without axis words"));
        }
        if b.mcodes.iter().any(|&m| m == 2 || m == 30) {
            self.end_program();
        }
        Ok(())
    }

    /// The modal settings a block sets before it moves, in GRBL's order: feed
    /// mode, plane, units, distance, WCS; then F (converted to mm/min with the
    /// block's units), S, T; then spindle and coolant.
    fn set_modes(&mut self, b: &BlockWords) -> Result<(), BlockError> {
        for &g in &b.gcodes {
            match g {
                930 => self.feed_mode = FeedMode::InverseTime,
                940 => self.feed_mode = FeedMode::UnitsPerMinute,
                170 => self.plane = Plane::XY,
                180 => self.plane = Plane::ZX,
                190 => self.plane = Plane::YZ,
                200 => self.units = Units::Inch,
                210 => self.units = Units::Mm,
                900 => self.distance = Distance::Absolute,
                910 => self.distance = Distance::Incremental,
                540..=590 => self.wcs = (g / 10) as u8,
                _ => {}
            }
        }
        if let Some(f) = b.v('F') {
            self.feed = Some(match self.units {
                Units::Inch => f * MM_PER_INCH,
                Units::Mm => f,
            });
        }
        if let Some(s) = b.v('S') {
            self.spindle_speed = s;
        }
        if let Some(t) = b.v('T') {
            if t.fract() != 0.0 {
                return Err(BlockError::new(23, "T needs an integer"));
            }
            if t > 255.0 {
                return Err(BlockError::new(38, "tool number above 255"));
            }
            self.tool = t as u32;
        }
        for &m in &b.mcodes {
            match m {
                3 => self.spindle = Spindle::Cw,
                4 => self.spindle = Spindle::Ccw,
                5 => self.spindle = Spindle::Off,
                7 => self.mist = true,
                8 => self.flood = true,
                9 => {
                    self.mist = false;
                    self.flood = false;
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Runs the non-modal command `nm` (G code ×10). `Ok(true)`: the block ends
    /// here (G4, G10, G28, G30, G92, G53 take the axis words for themselves);
    /// `Ok(false)`: G28.1, G30.1 and G92.1, which go on to the motion.
    fn run_non_modal(
        &mut self,
        nm: u32,
        b: &BlockWords,
        axes: &[Option<f64>; 3],
        scale: f64,
    ) -> Result<bool, BlockError> {
        match nm {
            40 => {
                if b.v('P').is_none() {
                    return Err(BlockError::new(28, "G4 needs a P word (dwell seconds)"));
                }
            }
            // G10 L2/L20 change work offsets: the work position is no longer known.
            100 => self.forget_axes(axes),
            280 | 300 => self.position = [None; 3],
            920 => {
                for (axis, value) in axes.iter().enumerate() {
                    if let Some(value) = value {
                        self.position[axis] = Some(value * scale);
                    }
                }
            }
            530 => {
                if !matches!(self.motion, Motion::Rapid | Motion::Linear) {
                    return Err(BlockError::new(30, "G53 only with G0 or G1"));
                }
                self.forget_axes(axes);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Marks the axes that have a word as of unknown work position.
    fn forget_axes(&mut self, axes: &[Option<f64>; 3]) {
        for (axis, value) in axes.iter().enumerate() {
            if value.is_some() {
                self.position[axis] = None;
            }
        }
    }

    /// `G43.1 Z<offset>` sets a tool length offset and G49 clears it: the Z word
    /// is the offset, not a move, and the work Z position is no longer known.
    /// Whether the block has either.
    fn apply_tool_length(&mut self, b: &BlockWords) -> Result<bool, BlockError> {
        let tool_length = b.gcodes.iter().any(|g| matches!(g, 431 | 490));
        if tool_length {
            if b.gcodes.contains(&431)
                && (b.v('Z').is_none() || b.v('X').is_some() || b.v('Y').is_some())
            {
                return Err(BlockError::new(
                    37,
                    "G43.1 takes exactly one axis word, Z (GRBL's tool length axis)",
                ));
            }
            self.position[2] = None;
        }
        Ok(tool_length)
    }

    /// A move with axis words needs a motion mode, and a feed move a feed rate
    /// (errors 31 and 22).
    fn check_feed(&self, b: &BlockWords) -> Result<(), BlockError> {
        match self.motion {
            Motion::None => Err(BlockError::new(31, "axis words with no motion mode (G80)")),
            Motion::Linear | Motion::ArcCw | Motion::ArcCcw | Motion::Probe(_) => {
                if self.feed_mode == FeedMode::UnitsPerMinute {
                    match self.feed {
                        None => return Err(BlockError::new(22, "feed move before any F word")),
                        // GRBL treats F0 as no feed rate at all.
                        Some(f) if f <= 0.0 => {
                            return Err(BlockError::new(22, "feed move at feed rate F0"))
                        }
                        Some(_) => {}
                    }
                }
                if self.feed_mode == FeedMode::InverseTime && !b.v('F').is_some_and(|f| f > 0.0) {
                    return Err(BlockError::new(
                        22,
                        "inverse-time feed move without a positive F",
                    ));
                }
                Ok(())
            }
            Motion::Rapid => Ok(()),
        }
    }

    /// GRBL's checks of an arc block (errors 32 to 35): an axis word and an R
    /// or offset word in its plane, and, where start and end are known, an R
    /// that reaches the end or an end on the circle of the I/J/K centre.
    fn check_arc(
        &self,
        b: &BlockWords,
        axes: &[Option<f64>; 3],
        scale: f64,
    ) -> Result<(), BlockError> {
        // In-plane axes and offset words: XY uses X/Y and I/J, ZX uses Z/X
        // and K/I, YZ uses Y/Z and J/K.
        let (axes_in_plane, offsets) = match self.plane {
            Plane::XY => (['X', 'Y'], ['I', 'J']),
            Plane::ZX => (['Z', 'X'], ['K', 'I']),
            Plane::YZ => (['Y', 'Z'], ['J', 'K']),
        };
        if axes_in_plane.iter().all(|&c| b.v(c).is_none()) {
            return Err(BlockError::new(32, "arc without an axis word in its plane"));
        }
        if b.v('R').is_none() && offsets.iter().all(|&c| b.v(c).is_none()) {
            return Err(BlockError::new(
                35,
                "arc without R or an offset word (I/J/K) in its plane",
            ));
        }
        let target = self.target(axes, scale);
        let start = self.position;
        let [a0, a1] = self.plane.axes();
        let (Some(s0), Some(s1), Some(t0), Some(t1)) =
            (start[a0], start[a1], target[a0], target[a1])
        else {
            return Ok(());
        };
        let (x, y) = (t0 - s0, t1 - s1);
        if let Some(r) = b.v('R') {
            if start == target {
                return Err(BlockError::new(
                    33,
                    "R arc ending where it starts (a full circle needs I/J/K)",
                ));
            }
            let r = r * scale;
            if 4.0 * r * r - x * x - y * y < 0.0 {
                return Err(BlockError::new(
                    34,
                    format!(
                        "arc radius R{} is less than half the distance {:.4} mm \
                         between start and end",
                        r / scale,
                        x.hypot(y) / 2.0
                    ),
                ));
            }
        } else {
            let i = b.v(offsets[0]).unwrap_or(0.0) * scale;
            let j = b.v(offsets[1]).unwrap_or(0.0) * scale;
            let r = i.hypot(j);
            let delta = ((x - i).hypot(y - j) - r).abs();
            if arc_radius_mismatch(r, delta) {
                return Err(BlockError::new(
                    33,
                    format!(
                        "arc end is {delta:.4} mm off the circle of radius {r:.4} \
                         mm (GRBL allows 0.005 mm, or 0.1 % of the radius)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// M2/M30: the program has ended, and GRBL restores these modes.
    fn end_program(&mut self) {
        self.ended = true;
        self.motion = Motion::Linear;
        self.distance = Distance::Absolute;
        self.plane = Plane::XY;
        self.feed_mode = FeedMode::UnitsPerMinute;
        self.wcs = 54;
        self.spindle = Spindle::Off;
        self.mist = false;
        self.flood = false;
    }

    /// Where a move with these axis words (in program units, `scale` mm per
    /// unit) ends, in mm: an axis without a word stays; `None` where unknown.
    fn target(&self, axes: &[Option<f64>; 3], scale: f64) -> [Option<f64>; 3] {
        let mut t = self.position;
        for (k, value) in axes.iter().enumerate() {
            if let Some(value) = value {
                t[k] = match self.distance {
                    Distance::Absolute => Some(value * scale),
                    Distance::Incremental => self.position[k].map(|p| p + value * scale),
                };
            }
        }
        t
    }

    /// The feed rate in mm/min, if set.
    pub fn feed_mm_per_min(&self) -> Option<f64> {
        self.feed
    }
}

impl Plane {
    /// Indices (0 = X, 1 = Y, 2 = Z) of the plane's first and second axes, in
    /// GRBL's order: XY for G17, ZX for G18, YZ for G19. The offset words follow
    /// the axes: I/J, K/I, J/K.
    pub(crate) fn axes(self) -> [usize; 2] {
        match self {
            Plane::XY => [0, 1],
            Plane::ZX => [2, 0],
            Plane::YZ => [1, 2],
        }
    }
}

/// GRBL's test for an I/J/K arc whose end is off the circle through its start
/// (error 33, `gc_execute_line`): the radii at start (`r`) and end differ by
/// `delta` > 0.005 mm **and** by more than 0.5 mm or 0.1 % of `r`. Both in mm.
pub(crate) fn arc_radius_mismatch(r: f64, delta: f64) -> bool {
    delta > 0.005 && (delta > 0.5 || delta > 0.001 * r)
}

fn frac(code10: u32) -> String {
    if code10 % 10 == 0 {
        String::new()
    } else {
        format!(".{}", code10 % 10)
    }
}

/// One line of a G-code file.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// 1-based line number in the file.
    pub(crate) number: usize,
    /// The line as written.
    pub raw: String,
    /// The block to send (see [`clean_line`]); empty for comment-only lines.
    pub block: String,
}

/// A G-code file as lines.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    /// Every line of the file, blank ones included, in order.
    pub lines: Vec<Line>,
}

impl Program {
    /// Splits a file into lines (never fails: a line's errors are found when it is executed).
    pub fn parse(text: &str) -> Program {
        Program {
            lines: text
                .lines()
                .enumerate()
                .map(|(i, raw)| Line {
                    number: i + 1,
                    raw: raw.to_string(),
                    block: clean_line(raw),
                })
                .collect(),
        }
    }

    /// Lines with something to send.
    pub(crate) fn blocks(&self) -> impl Iterator<Item = &Line> {
        self.lines.iter().filter(|l| !l.block.is_empty())
    }

    /// Runs every line through a fresh [`ModalState`]; returns every error (a
    /// failing line leaves the state unchanged, as in GRBL).
    #[cfg(test)]
    pub(crate) fn check(&self) -> Vec<LineError> {
        let mut state = ModalState::default();
        let mut errors = Vec::new();
        for line in self.blocks() {
            if line.block.starts_with('$') {
                continue;
            }
            if let Err(error) = state.execute(&line.block) {
                errors.push(LineError {
                    line: line.number,
                    text: line.block.clone(),
                    error,
                });
            }
        }
        errors
    }

    /// The modal state in force when line `number` (1-based) starts, i.e. after
    /// lines `1 .. number`. Fails on the first invalid line before it.
    pub fn state_before(&self, number: usize) -> Result<ModalState, LineError> {
        let mut state = ModalState::default();
        for line in self.blocks().take_while(|l| l.number < number) {
            if line.block.starts_with('$') {
                continue;
            }
            state.execute(&line.block).map_err(|error| LineError {
                line: line.number,
                text: line.block.clone(),
                error,
            })?;
        }
        Ok(state)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(blocks: &[&str]) -> Result<ModalState, BlockError> {
        let mut s = ModalState::default();
        for b in blocks {
            s.execute(&clean_line(b))?;
        }
        Ok(s)
    }

    #[test]
    fn cleans_comments_and_whitespace() {
        assert_eq!(clean_line("g1 x1 (move) y2 ; tail"), "G1X1Y2");
        assert_eq!(clean_line("(only a comment)"), "");
        assert_eq!(clean_line(" % "), "");
        assert_eq!(clean_line("G0 X1 (unclosed"), "G0X1");
        assert_eq!(clean_line("/G0 X1\u{1}"), "G0X1");
        assert!(has_block_delete("/G0 X1"));
        assert!(!has_block_delete("G0 X1 (a/b) ; c/d"));
    }

    #[test]
    fn tokenizes_numbers() {
        let w = tokenize("G1X-1.5Y+.25F300").unwrap();
        assert_eq!(w.len(), 4);
        assert_eq!(
            w[1],
            Word {
                letter: 'X',
                value: -1.5
            }
        );
        assert_eq!(w[2].value, 0.25);
        assert_eq!(tokenize("G1X").unwrap_err().code, 2);
        assert_eq!(tokenize("G1X1..2").unwrap_err().code, 2);
        assert_eq!(tokenize("12").unwrap_err().code, 1);
    }

    #[test]
    fn grbl_error_codes_for_bad_words() {
        assert_eq!(run(&["G41 X1"]).unwrap_err().code, 20);
        assert_eq!(run(&["G81 X1 Y1 Z-1 R1 F100"]).unwrap_err().code, 20);
        assert_eq!(run(&["G1 E5"]).unwrap_err().code, 20);
        // GRBL sees G1 claim the axis words G0 already has before the group clash.
        assert_eq!(run(&["G0 G1 X1"]).unwrap_err().code, 24);
        assert_eq!(run(&["G90 G91 X1"]).unwrap_err().code, 21);
        assert_eq!(run(&["G1 X1"]).unwrap_err().code, 22);
        assert_eq!(run(&["G0 X1 X2"]).unwrap_err().code, 25);
        assert_eq!(run(&["G59.1"]).unwrap_err().code, 29);
        assert_eq!(run(&["G80", "X1"]).unwrap_err().code, 31);
        assert_eq!(run(&["F100", "G2 X1 Y1"]).unwrap_err().code, 35);
        assert_eq!(run(&["S-1"]).unwrap_err().code, 4);
        assert!(run(&["G38.2 Z-5 F50"]).is_ok());
        assert_eq!(run(&["F100", "G2 Z1 I1"]).unwrap_err().code, 32);
        assert_eq!(run(&["F100", "G2 X1 K1"]).unwrap_err().code, 35);
        assert_eq!(run(&["F100", "G1 X1 I1"]).unwrap_err().code, 36);
        assert_eq!(run(&["G0 X1 P2"]).unwrap_err().code, 36);
        assert_eq!(run(&["G2"]).unwrap_err().code, 26);
        assert_eq!(run(&["N1.5 G0 X1"]).unwrap_err().code, 27);
        assert!(run(&["F100", "G18 G2 X1 Z1 K1"]).is_ok());
        assert!(run(&["G4 P0.5", "N10 G1 X1 F5", "G1"]).is_ok());
        assert_eq!(run(&["M7 M8"]).unwrap_err().code, 21);
        assert!(run(&["M7", "M8"]).is_ok());
        assert_eq!(run(&["G4 P1 G53 G0 X0"]).unwrap_err().code, 21);
        assert_eq!(run(&["G28 G0 X0"]).unwrap_err().code, 24);
        assert_eq!(run(&["G1 G92 X0 F10"]).unwrap_err().code, 24);
        assert!(run(&["G53 G0 X0"]).is_ok());
        assert_eq!(run(&["G1.5 X1 F10"]).unwrap_err().code, 23);
        assert_eq!(run(&["M3.5"]).unwrap_err().code, 23);
        assert_eq!(run(&["G43.1 X1"]).unwrap_err().code, 37);
        assert_eq!(run(&["G43.1"]).unwrap_err().code, 37);
        let s = run(&["G0 X1 Y2 Z3", "G43.1 Z-0.5"]).unwrap();
        assert_eq!(s.position, [Some(1.0), Some(2.0), None]);
        assert_eq!(run(&["F0", "G1 X1"]).unwrap_err().code, 22);
        assert_eq!(run(&["G43 Z1"]).unwrap_err().code, 20);
    }

    #[test]
    fn arc_geometry_as_grbl_checks_it() {
        let base = ["G0 X0 Y0 Z0", "F100"];
        let with = |b: &str| run(&[base[0], base[1], b]);
        assert!(with("G2 X10 Y0 I5 J0").is_ok());
        // 0.004 mm off: under 0.005 mm, accepted.
        assert!(with("G2 X10.004 Y0 I5 J0").is_ok());
        // 0.006 mm off a 5 mm radius: over 0.005 and over 0.1 % (0.005 mm).
        assert_eq!(with("G2 X10.006 Y0 I5 J0").unwrap_err().code, 33);
        // 0.04 mm off a 100 mm radius: over 0.005 but under 0.1 % (0.1 mm).
        assert!(with("G2 X200.04 Y0 I100 J0").is_ok());
        assert_eq!(with("G2 X200.6 Y0 I100 J0").unwrap_err().code, 33);
        assert!(with("G2 X10 R5").is_ok());
        assert_eq!(with("G2 X10 R4.9").unwrap_err().code, 34);
        assert_eq!(with("G2 X0 Y0 R5").unwrap_err().code, 33);
        assert!(with("G3 X0 Y0 I5").is_ok(), "full circle with I/J");
        // Inches: I0.5 is 12.7 mm; the end X1 is 25.4 mm.
        assert!(run(&["G20 G0 X0 Y0", "G2 X1 Y0 I0.5 F10"]).is_ok());
        // G18 (ZX): K/I offsets.
        assert!(with("G18 G2 X10 Z0 I5 K0").is_ok());
        assert_eq!(with("G18 G2 X10 Z1 I5 K0").unwrap_err().code, 33);
        // Unknown start: nothing to check.
        assert!(run(&["F100", "G2 X10.3 Y0 I5 J0"]).is_ok());
    }

    #[test]
    fn tracks_modal_state_and_position() {
        let s = run(&[
            "G20 G91",
            "G0 X1",
            "G90 G0 X1 Y2 Z0.5",
            "G91 G1 X1 F10",
            "M4 S9000 M8",
            "G18",
            "G55",
        ])
        .unwrap();
        assert_eq!(s.units, Units::Inch);
        assert_eq!(s.distance, Distance::Incremental);
        assert_eq!(s.plane, Plane::ZX);
        assert_eq!(s.wcs, 55);
        assert_eq!(s.motion, Motion::Linear);
        assert_eq!(s.feed, Some(254.0));
        let s2 = run(&["G20 F10", "G21"]).unwrap();
        assert_eq!(s2.feed, Some(254.0), "F is kept in mm/min across G21");
        assert_eq!(s.spindle, Spindle::Ccw);
        assert_eq!(s.spindle_speed, 9000.0);
        assert!(s.flood && !s.mist);
        assert!((s.position[0].unwrap() - 50.8).abs() < 1e-9);
        assert!((s.position[1].unwrap() - 50.8).abs() < 1e-9);
        assert!((s.position[2].unwrap() - 12.7).abs() < 1e-9);
        let s = run(&["G0 X1 Y1 Z1", "G28"]).unwrap();
        assert_eq!(s.position, [None; 3]);
    }

    #[test]
    fn error_leaves_state_unchanged() {
        let mut s = ModalState::default();
        s.execute("G1X1F100").unwrap();
        let before = s.clone();
        assert!(s.execute("G20G41X5").is_err());
        assert_eq!(s, before);
    }

    #[test]
    fn program_state_before_line() {
        let p = Program::parse("G21 G90\n(c)\nM3 S1000\nG1 X5 F200\nG1 X6\nM5\n");
        let s = p.state_before(5).unwrap();
        assert_eq!(s.position[0], Some(5.0));
        assert_eq!(s.spindle, Spindle::Cw);
        let p = Program::parse("G1 X1 F1\nG41\nG1 X2\n");
        let errs = p.check();
        assert_eq!(errs.len(), 1);
        assert_eq!(errs[0].line, 2);
        assert_eq!(p.state_before(3).unwrap_err().line, 2);
    }
}
