//! GRBL 1.1 messages: real-time bytes, response lines, status reports.
//!
//! Every line GRBL sends is one of: a response (`ok`, `error:N`), a status report
//! (`<...>`), an alarm (`ALARM:N`), the welcome banner (`Grbl 1.1h ['$' for help]`),
//! a feedback message in brackets (`[MSG:...]`, `[GC:...]`, `[PRB:...]`, ...), a
//! startup-line echo (`>G54:ok`), or a settings line (`$0=10`). Only `ok` and
//! `error:N` acknowledge a streamed line.

/// `?`: ask for a status report.
pub const STATUS_QUERY: u8 = b'?';
/// `!`: feed hold (decelerate to a controlled stop, keep position).
pub const FEED_HOLD: u8 = b'!';
/// `~`: cycle start / resume from a hold.
pub const CYCLE_START: u8 = b'~';
/// Ctrl-X: soft reset (stops everything, spindle and coolant off).
pub const SOFT_RESET: u8 = 0x18;

/// GRBL 1.1's override real-time commands (bytes 0x90 to 0x9D; feed and spindle
/// overrides step in percent and are clamped by GRBL to 10 to 200 %, rapids are
/// 100, 50 or 25 %).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Override {
    /// 0x90: feed override back to 100 %.
    FeedReset,
    /// 0x91: feed +10 %.
    FeedUp10,
    /// 0x92: feed −10 %.
    FeedDown10,
    /// 0x93: feed +1 %.
    FeedUp1,
    /// 0x94: feed −1 %.
    FeedDown1,
    /// 0x95: rapids at 100 %.
    Rapid100,
    /// 0x96: rapids at 50 %.
    Rapid50,
    /// 0x97: rapids at 25 %.
    Rapid25,
    /// 0x99: spindle override back to 100 %.
    SpindleReset,
    /// 0x9A: spindle +10 %.
    SpindleUp10,
    /// 0x9B: spindle −10 %.
    SpindleDown10,
    /// 0x9C: spindle +1 %.
    SpindleUp1,
    /// 0x9D: spindle −1 %.
    SpindleDown1,
}

impl Override {
    /// The real-time byte GRBL 1.1 reads for it.
    pub fn byte(self) -> u8 {
        match self {
            Override::FeedReset => 0x90,
            Override::FeedUp10 => 0x91,
            Override::FeedDown10 => 0x92,
            Override::FeedUp1 => 0x93,
            Override::FeedDown1 => 0x94,
            Override::Rapid100 => 0x95,
            Override::Rapid50 => 0x96,
            Override::Rapid25 => 0x97,
            Override::SpindleReset => 0x99,
            Override::SpindleUp10 => 0x9A,
            Override::SpindleDown10 => 0x9B,
            Override::SpindleUp1 => 0x9C,
            Override::SpindleDown1 => 0x9D,
        }
    }
}

/// One line from GRBL, classified.
#[derive(Clone, Debug, PartialEq)]
pub enum Response {
    /// `ok`: the oldest unacknowledged line was accepted.
    Ok,
    /// `error:N`: the oldest unacknowledged line was rejected.
    Error(u8),
    /// `ALARM:N`: GRBL stopped and locked out G-code.
    Alarm(u8),
    /// `<...>` status report.
    Status(StatusReport),
    /// Welcome banner after a (soft) reset, with the version (`1.1h`).
    Banner {
        /// Version word after `Grbl`.
        version: String,
    },
    /// A bracketed push message: `[MSG:...]`, `[GC:...]`, `[PRB:...]`, `[VER:...]` ...
    Feedback(String),
    /// Echo of a startup line (`>G54:ok`): not an acknowledgement.
    StartupEcho(String),
    /// Anything else (settings lines, text from something that is not GRBL).
    Other(String),
}

/// Parses one line (without its line ending).
pub fn parse_response(line: &str) -> Response {
    let line = line.trim();
    if line == "ok" {
        return Response::Ok;
    }
    if let Some(n) = line.strip_prefix("error:") {
        if let Ok(n) = n.trim().parse() {
            return Response::Error(n);
        }
    }
    if let Some(n) = line.strip_prefix("ALARM:") {
        if let Ok(n) = n.trim().parse() {
            return Response::Alarm(n);
        }
    }
    if line.starts_with('<') && line.ends_with('>') {
        if let Some(report) = StatusReport::parse(line) {
            return Response::Status(report);
        }
    }
    if line.starts_with('[') && line.ends_with(']') {
        return Response::Feedback(line.to_string());
    }
    if let Some(rest) = line.strip_prefix('>') {
        return Response::StartupEcho(rest.to_string());
    }
    // "Grbl 1.1h ['$' for help]" (and grblHAL's "GrblHAL 1.1f ['$' or '$HELP' for help]").
    let lower = line.to_ascii_lowercase();
    if lower.starts_with("grbl") && lower.contains("for help]") {
        let version = line
            .split_whitespace()
            .nth(1)
            .unwrap_or_default()
            .to_string();
        return Response::Banner { version };
    }
    Response::Other(line.to_string())
}

/// GRBL's machine state, first field of a status report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MachineState {
    /// Idle.
    Idle,
    /// Run: executing motion.
    Run,
    /// Hold:0 (stopped, resumable) or Hold:1 (still decelerating).
    Hold(u8),
    /// Jog.
    Jog,
    /// Alarm: G-code locked out.
    Alarm,
    /// Door:N.
    Door(u8),
    /// Check mode (`$C`).
    Check,
    /// Homing.
    Home,
    /// Sleep.
    Sleep,
    /// Something else.
    Unknown(String),
}

impl MachineState {
    fn parse(s: &str) -> MachineState {
        let (name, sub) = match s.split_once(':') {
            Some((n, d)) => (n, d.parse().unwrap_or(0)),
            None => (s, 0),
        };
        match name {
            "Idle" => MachineState::Idle,
            "Run" => MachineState::Run,
            "Hold" => MachineState::Hold(sub),
            "Jog" => MachineState::Jog,
            "Alarm" => MachineState::Alarm,
            "Door" => MachineState::Door(sub),
            "Check" => MachineState::Check,
            "Home" => MachineState::Home,
            "Sleep" => MachineState::Sleep,
            other => MachineState::Unknown(other.to_string()),
        }
    }
}

impl std::fmt::Display for MachineState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MachineState::Hold(n) => write!(f, "Hold:{n}"),
            MachineState::Door(n) => write!(f, "Door:{n}"),
            MachineState::Unknown(s) => f.write_str(s),
            other => write!(f, "{other:?}"),
        }
    }
}

/// A parsed `<...>` status report. Positions are X, Y, Z (further axes ignored).
#[derive(Clone, Debug, PartialEq)]
pub struct StatusReport {
    /// Machine state.
    pub state: MachineState,
    /// `MPos:` machine position.
    pub mpos: Option<[f64; 3]>,
    /// `WPos:` work position.
    pub wpos: Option<[f64; 3]>,
    /// `WCO:` work coordinate offset (sent only now and then).
    pub wco: Option<[f64; 3]>,
    /// `Bf:` free planner blocks and free receive-buffer bytes.
    pub buffer: Option<(u32, u32)>,
    /// `Ln:` line number being executed (`N` word).
    pub line_number: Option<u32>,
    /// `F:`/`FS:` feed (and spindle speed).
    pub feed: Option<f64>,
    /// `FS:` spindle speed.
    pub speed: Option<f64>,
    /// `Ov:` feed, rapid, spindle overrides in percent.
    pub overrides: Option<[u32; 3]>,
    /// `Pn:` input pins.
    pub pins: Option<String>,
}

fn triple(s: &str) -> Option<[f64; 3]> {
    let mut it = s.split(',').map(|v| v.trim().parse::<f64>());
    Some([it.next()?.ok()?, it.next()?.ok()?, it.next()?.ok()?])
}

impl StatusReport {
    /// Parses `<Idle|MPos:0.000,0.000,0.000|FS:0,0>`; `None` if it is not one.
    pub fn parse(line: &str) -> Option<StatusReport> {
        let inner = line.trim().strip_prefix('<')?.strip_suffix('>')?;
        let mut fields = inner.split('|');
        let state = MachineState::parse(fields.next()?);
        let mut r = StatusReport {
            state,
            mpos: None,
            wpos: None,
            wco: None,
            buffer: None,
            line_number: None,
            feed: None,
            speed: None,
            overrides: None,
            pins: None,
        };
        for field in fields {
            let Some((key, value)) = field.split_once(':') else {
                continue;
            };
            match key {
                "MPos" => r.mpos = triple(value),
                "WPos" => r.wpos = triple(value),
                "WCO" => r.wco = triple(value),
                "Bf" => {
                    let (a, b) = value.split_once(',')?;
                    r.buffer = Some((a.parse().ok()?, b.parse().ok()?));
                }
                "Ln" => r.line_number = value.parse().ok(),
                "F" => r.feed = value.parse().ok(),
                "FS" => {
                    let (f, s) = value.split_once(',')?;
                    r.feed = f.parse().ok();
                    r.speed = s.parse().ok();
                }
                "Ov" => {
                    let mut it = value.split(',').map(|v| v.parse::<u32>().ok());
                    r.overrides = Some([it.next()??, it.next()??, it.next()??]);
                }
                "Pn" => r.pins = Some(value.to_string()),
                _ => {}
            }
        }
        Some(r)
    }

    /// Work position: `WPos` if reported, else `MPos − WCO` with this report's WCO
    /// or else `wco`, the last one GRBL reported. `None` when neither is known:
    /// machine position is not work position.
    pub fn work_position(&self, wco: Option<[f64; 3]>) -> Option<[f64; 3]> {
        if let Some(w) = self.wpos {
            return Some(w);
        }
        let m = self.mpos?;
        let o = self.wco.or(wco)?;
        Some([m[0] - o[0], m[1] - o[1], m[2] - o[2]])
    }
}

/// Where the tool is, as well as the status reports tell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Position {
    /// Work coordinates (what the program says): `WPos`, or `MPos − WCO`.
    Work([f64; 3]),
    /// Machine coordinates: `MPos` before GRBL has reported any `WCO`.
    Machine([f64; 3]),
}

impl std::fmt::Display for Position {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (name, p, note) = match self {
            Position::Work(p) => ("WPos", p, ""),
            Position::Machine(p) => ("MPos", p, " (work offset not reported yet)"),
        };
        write!(f, "{name} X{:.3} Y{:.3} Z{:.3}{note}", p[0], p[1], p[2])
    }
}

/// Tracks GRBL's work coordinate offset. GRBL 1.1 sends `WCO:` only in some
/// status reports (every 10th when idle, every 30th when busy, and after it
/// changes), so the last one seen applies to the reports without it: work
/// position = `MPos − WCO`. A report with `WPos` (`$10` without bit 0) is used as is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorkOffset {
    wco: Option<[f64; 3]>,
}

impl WorkOffset {
    /// Takes in a report (its `WCO`, if any) and says where the tool is.
    pub fn update(&mut self, r: &StatusReport) -> Option<Position> {
        if r.wco.is_some() {
            self.wco = r.wco;
        }
        match r.work_position(self.wco) {
            Some(w) => Some(Position::Work(w)),
            None => r.mpos.map(Position::Machine),
        }
    }

    /// The last `WCO` GRBL reported.
    pub fn wco(&self) -> Option<[f64; 3]> {
        self.wco
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classifies_lines() {
        assert_eq!(parse_response("ok"), Response::Ok);
        assert_eq!(parse_response("error:22"), Response::Error(22));
        assert_eq!(parse_response("ALARM:1"), Response::Alarm(1));
        assert_eq!(
            parse_response("Grbl 1.1h ['$' for help]"),
            Response::Banner {
                version: "1.1h".into()
            }
        );
        assert_eq!(
            parse_response(">G54:ok"),
            Response::StartupEcho("G54:ok".into())
        );
        assert!(matches!(
            parse_response("[MSG:Caution: Unlocked]"),
            Response::Feedback(_)
        ));
        assert!(matches!(
            parse_response("[GC:G0 G54 G17]"),
            Response::Feedback(_)
        ));
        assert!(matches!(parse_response("okay"), Response::Other(_)));
    }

    #[test]
    fn parses_status_reports() {
        let r = StatusReport::parse(
            "<Hold:0|MPos:1.000,-2.500,3.000|Bf:15,128|Ln:99|FS:500,12000|Ov:100,50,110|WCO:1,1,1>",
        )
        .unwrap();
        assert_eq!(r.state, MachineState::Hold(0));
        assert_eq!(r.mpos, Some([1.0, -2.5, 3.0]));
        assert_eq!(r.buffer, Some((15, 128)));
        assert_eq!(r.line_number, Some(99));
        assert_eq!(r.feed, Some(500.0));
        assert_eq!(r.speed, Some(12000.0));
        assert_eq!(r.overrides, Some([100, 50, 110]));
        assert_eq!(r.work_position(None), Some([0.0, -3.5, 2.0]));
        let r = StatusReport::parse("<Idle|WPos:1,2,3|F:0>").unwrap();
        assert_eq!(r.work_position(None), Some([1.0, 2.0, 3.0]));
        assert!(StatusReport::parse("<>").is_some_and(|r| r.mpos.is_none()));
        // MPos without any WCO is not a work position.
        let r = StatusReport::parse("<Idle|MPos:5,6,7>").unwrap();
        assert_eq!(r.work_position(None), None);
        assert_eq!(
            r.work_position(Some([1.0, 1.0, 1.0])),
            Some([4.0, 5.0, 6.0])
        );
        assert!(StatusReport::parse("Idle").is_none());
    }
}
