//! `pfcam stream` against a GRBL 1.1 emulator on a real pseudo-terminal.
//!
//! The emulator (`tests/grbl/emulator.rs`, test support only) fails a test when the
//! streamer overflows its 128-byte receive buffer. Every wait here is bounded.
//!
//! A test binary of its own, not a module of `tests/all`: these tests wait on
//! a pty with timeouts, and beside the numeric tests of `all` on two cores
//! they were starved into a failure (`error_stops_the_stream_with_hold_and_reset`:
//! the emulator accepted lines the streamer had not yet seen acknowledged).

// Shared with `tests/all`, which uses the readers this binary does not.
#[allow(dead_code)]
#[path = "../all/doc_figures.rs"]
mod doc_figures;
mod emulator;
/// `pfcam stream`'s terminal side (exit codes, messages), from the binary.
#[path = "../../src/cli/stream/mod.rs"]
mod stream;

use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, Sender};
use std::time::Duration;

use emulator::{Config, Emulator, Personality};
use pfcam::gcode::parse::{Motion, Program};
use pfcam::grbl::protocol::{Position, StatusReport, WorkOffset, FEED_HOLD, SOFT_RESET};
use pfcam::grbl::{job_blocks, run_stream};
use pfcam::grbl::{
    Event, GrblError, Link, Observer, OperatorCommand, Settings, StreamOptions as StreamArgs,
    StreamReport, Streamer,
};
use stream::ExitStatus;

/// Writes `text` to a file unique to this test process.
fn job_file(name: &str, text: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("pfcam-grbl-{}-{name}.nc", std::process::id()));
    std::fs::write(&path, text).expect("write job");
    path
}

/// A realistic job: header, `n` short G1 segments in a zigzag, footer.
fn zigzag(n: usize) -> String {
    let mut s = String::from(
        "%\n(pfcam test job)\nG21 G90 G17 G54\nG0 Z5.000\nM3 S12000\nM8\nG0 X0.000 Y0.000\nG1 Z-0.500 F300\n",
    );
    for i in 0..n {
        let row = i / 100;
        let col = i % 100;
        let x = if row % 2 == 0 {
            col as f64 * 0.5
        } else {
            (99 - col) as f64 * 0.5
        };
        let y = row as f64 * 0.5 + col as f64 * 0.001;
        s.push_str(&format!("G1 X{x:.3} Y{y:.3} F800 ; segment {i}\n"));
    }
    s.push_str("G0 Z5.000\nM9\nM5\nM30\n%\n");
    s
}

fn args(emu: &Emulator, file: &Path) -> StreamArgs {
    let mut a = StreamArgs::new(file, emu.path.clone());
    a.connect_timeout = 0.3;
    a.status_hz = 50.0;
    a.response_timeout = 3.0;
    a.spindle_delay = 0.5;
    a
}

/// Keeps the events (as text) and forwards them to a channel for tests that react.
struct Recorder {
    events: Vec<String>,
    tx: Option<Sender<String>>,
}

impl Recorder {
    fn new() -> Recorder {
        Recorder {
            events: Vec::new(),
            tx: None,
        }
    }
}

impl Observer for Recorder {
    fn event(&mut self, event: Event<'_>) {
        let text = match event {
            Event::Status(_) | Event::Progress { .. } => return,
            other => format!("{other:?}"),
        };
        if let Some(tx) = &self.tx {
            let _ = tx.send(text.clone());
        }
        self.events.push(text);
    }
}

fn run(a: &StreamArgs) -> (Result<StreamReport, GrblError>, Vec<String>) {
    let (_tx, rx) = mpsc::channel();
    let mut rec = Recorder::new();
    let r = run_stream(a, &rx, &mut rec);
    (r, rec.events)
}

/// Runs the stream in a thread; returns the operator's sender, the event channel
/// and a channel that yields the outcome.
fn spawn(
    a: StreamArgs,
) -> (
    Sender<OperatorCommand>,
    Receiver<String>,
    Receiver<Result<StreamReport, GrblError>>,
) {
    let (op_tx, op_rx) = mpsc::channel();
    let (ev_tx, ev_rx) = mpsc::channel();
    let (done_tx, done_rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut rec = Recorder {
            events: Vec::new(),
            tx: Some(ev_tx),
        };
        let r = run_stream(&a, &op_rx, &mut rec);
        let _ = done_tx.send(r);
    });
    (op_tx, ev_rx, done_rx)
}

fn wait_event(events: &Receiver<String>, what: &str) {
    loop {
        match events.recv_timeout(Duration::from_secs(20)) {
            Ok(e) if e.contains(what) => return,
            Ok(_) => {}
            Err(_) => panic!("no {what} event"),
        }
    }
}

fn outcome(done: &Receiver<Result<StreamReport, GrblError>>) -> Result<StreamReport, GrblError> {
    done.recv_timeout(Duration::from_secs(30))
        .expect("the streamer hung")
}

fn assert_no_overflow(emu: &Emulator) {
    let s = emu.shared();
    assert!(s.overflow.is_none(), "{:?}", s.overflow);
    assert!(s.max_rx <= 128, "max rx {}", s.max_rx);
}

fn file_blocks(a: &StreamArgs) -> Vec<String> {
    job_blocks(a)
        .expect("job")
        .1
        .into_iter()
        .map(|b| b.text)
        .collect()
}

#[test]
fn whole_job_streams_in_order_within_the_buffer() {
    let emu = Emulator::start(Config {
        speedup: 150.0,
        startup_echo: true,
        ..Config::default()
    });
    let file = job_file("whole", &zigzag(3000));
    let mut a = args(&emu, &file);
    let log = std::env::temp_dir().join(format!("pfcam-grbl-{}-whole.log", std::process::id()));
    a.log = Some(log.clone());
    let (r, events) = run(&a);
    // Push messages are shown, never taken for acknowledgements.
    assert!(events.iter().any(|e| e.contains(">G54:ok")), "{events:?}");
    assert!(
        events.iter().any(|e| e.contains("[MSG:Pgm End]")),
        "{events:?}"
    );
    let report = r.expect("stream completes");
    let sent = file_blocks(&a);
    assert_eq!(report.acked, sent.len());
    assert!(report.faults.is_empty());
    assert_eq!(emu.lines(), sent, "every line arrives once, in order");
    assert_no_overflow(&emu);
    assert!(report.max_in_flight <= 128);
    // The planner is the bottleneck here: the receive buffer stays nearly full.
    assert!(report.mean_fill > 0.7, "mean fill {}", report.mean_fill);
    assert_eq!(
        Some(report.acked),
        doc_lines("planner-bound emulator (`speedup` 150)"),
        "docs/grbl.md's line count"
    );
    println!(
        "throttled emulator: {} lines in {:.2} s = {:.0} lines/s, mean buffer fill {:.1}%, max {} bytes",
        report.acked,
        report.elapsed.as_secs_f64(),
        report.acked as f64 / report.elapsed.as_secs_f64(),
        report.mean_fill * 100.0,
        report.max_in_flight
    );
    assert_eq!(
        emu.shared().state,
        "Idle",
        "completed means the machine is idle"
    );
    let log = std::fs::read_to_string(&log).expect("log written");
    assert!(log.contains("> G1X0.500Y0.001F800"), "sent lines logged");
    assert!(log.contains("< ok"), "responses logged");
    assert!(log.contains("< Grbl 1.1h"), "banner logged");
}

#[test]
fn fast_emulator_keeps_the_buffer_mostly_full() {
    let emu = Emulator::start(Config {
        speedup: 1e7,
        ..Config::default()
    });
    let file = job_file("fast", &zigzag(5000));
    let a = args(&emu, &file);
    let (r, _) = run(&a);
    let report = r.expect("stream completes");
    assert_eq!(emu.lines(), file_blocks(&a));
    assert_no_overflow(&emu);
    assert_eq!(
        Some(report.acked),
        doc_lines("fast emulator (planner never full)"),
        "docs/grbl.md's line count"
    );
    println!(
        "fast emulator: {} lines in {:.2} s = {:.0} lines/s, mean buffer fill {:.1}%",
        report.acked,
        report.elapsed.as_secs_f64(),
        report.acked as f64 / report.elapsed.as_secs_f64(),
        report.mean_fill * 100.0
    );
    assert!(report.mean_fill > 0.5, "mean fill {}", report.mean_fill);
}

fn with_errors() -> String {
    let mut s = String::from("G21 G90\nG0 Z5\nG1 Z-1 F200\n");
    for i in 4..=200 {
        match i {
            50 => s.push_str("G41 X10 (cutter comp: GRBL has none)\n"),
            120 => s.push_str("G81 X1 Y1 Z-2 R1\n"),
            _ => s.push_str(&format!(
                "G1 X{:.2} Y{:.2}\n",
                i as f64 * 0.1,
                (i % 7) as f64
            )),
        }
    }
    s
}

#[test]
fn error_stops_the_stream_with_hold_and_reset() {
    let emu = Emulator::start(Config::default());
    let file = job_file("error-stop", &with_errors());
    let a = args(&emu, &file);
    let (r, _) = run(&a);
    let err = r.expect_err("error stops");
    match &err {
        GrblError::Rejected {
            fault,
            last_acked,
            resume_from,
        } => {
            assert_eq!(fault.line, 50);
            assert_eq!(fault.code, 20);
            assert_eq!(fault.text, "G41X10");
            // Lines already in GRBL's buffer behind the bad one are still accepted.
            let last = last_acked.expect("acked");
            assert!(last >= 49, "{last}");
            let last_accepted = emu
                .shared()
                .received
                .iter()
                .rev()
                .find(|r| r.error.is_none())
                .map(|r| r.text.clone());
            assert_eq!(
                Some(Program::parse(&with_errors()).lines[last - 1].block.clone()),
                last_accepted
            );
            // Resume no later than the rejected line.
            assert!(resume_from.is_some_and(|r| r <= 50), "{resume_from:?}");
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("line 50"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::GrblError);
    let s = emu.shared();
    let rt: Vec<u8> = s.realtime.iter().map(|r| r.0).collect();
    assert!(
        rt.ends_with(&[FEED_HOLD, SOFT_RESET]),
        "hold, then reset: {rt:?}"
    );
    assert!(!s.spindle_on);
    // Only what was already in the buffer can follow line 50.
    let after: usize = s.received.iter().skip_while(|r| r.error.is_none()).count();
    assert!(after < 20, "{after} lines after the error");
    drop(s);
    assert_no_overflow(&emu);
}

#[test]
fn rejected_line_is_named_with_a_resume_line_that_skips_no_move() {
    let emu = Emulator::start(Config::default());
    let text = with_errors();
    let file = job_file("error-advice", &text);
    let a = args(&emu, &file);
    let (r, _) = run(&a);
    let err = r.expect_err("error stops");
    let GrblError::Rejected {
        fault,
        last_acked,
        resume_from,
    } = &err
    else {
        panic!("unexpected {err:?}");
    };
    assert_eq!(fault.line, 50);
    assert!(
        last_acked.is_some_and(|l| l > 50),
        "lines after it were acked"
    );
    // The moves the reset threw away: those before line 50 must all be re-run, so
    // the resume line is the oldest of them, exactly.
    let program = Program::parse(&text);
    let file_line = |t: &String| {
        program
            .lines
            .iter()
            .position(|l| &l.block == t)
            .map(|i| i + 1)
            .expect("a file line")
    };
    let flushed_before: Vec<usize> = emu
        .shared()
        .flushed
        .iter()
        .map(file_line)
        .filter(|&l| l < 50)
        .collect();
    let resume = resume_from.expect("a resume line");
    assert_eq!(
        Some(resume),
        flushed_before.iter().copied().min().or(Some(50)),
        "flushed before the fault: {flushed_before:?}"
    );
    let advice = stream::stop_advice(&err, &a, Some(&program)).join("\n");
    assert!(
        advice.contains("rejected: line 50: `G41 X10 (cutter comp: GRBL has none)`"),
        "{advice}"
    );
    assert!(
        advice.contains(&format!("--from-line {resume}")),
        "{advice}"
    );
    // The last acknowledged line follows the rejected one: not offered as news.
    assert!(!advice.contains("last line acknowledged"), "{advice}");
}

#[test]
fn continue_on_error_lists_rejected_lines() {
    let emu = Emulator::start(Config::default());
    let file = job_file("continue", &with_errors());
    let mut a = args(&emu, &file);
    a.continue_on_error = true;
    let (r, events) = run(&a);
    let report = r.expect("completes");
    let lines: Vec<(usize, u8)> = report.faults.iter().map(|f| (f.line, f.code)).collect();
    assert_eq!(lines, [(50, 20), (120, 20)]);
    assert_eq!(emu.lines().len(), 200);
    assert_eq!(
        events.iter().filter(|e| e.starts_with("Rejected")).count(),
        2
    );
    assert_eq!(ExitStatus::of(&Ok(report)), ExitStatus::GrblError);
    assert_no_overflow(&emu);
}

#[test]
fn alarm_mid_job_stops_and_sends_nothing_more() {
    let emu = Emulator::start(Config {
        alarm_after: Some((300, 1)),
        ..Config::default()
    });
    let file = job_file("alarm", &zigzag(1000));
    let a = args(&emu, &file);
    let (r, _) = run(&a);
    let err = r.expect_err("alarm stops");
    match &err {
        GrblError::Alarm {
            code, last_acked, ..
        } => {
            assert_eq!(*code, 1);
            // The 300th line sent is file line 302 (`%` and the comment are not sent).
            let last = last_acked.expect("some line was acknowledged");
            assert!(last <= 302 && last > 250, "last acked {last}");
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("hard limit"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::Alarm);
    let s = emu.shared();
    assert_eq!(s.state, "Alarm");
    // After the alarm only bytes already on their way can arrive (GRBL answers
    // them with error:9): at most one receive buffer's worth.
    let late: usize = s
        .received
        .iter()
        .filter(|r| r.error == Some(9))
        .map(|r| r.text.len() + 1)
        .sum();
    assert!(late <= 128, "{late} bytes sent after the alarm");
    drop(s);
    assert_no_overflow(&emu);
}

#[test]
fn alarm_at_connect_is_reported_not_cleared() {
    let emu = Emulator::start(Config {
        start_in_alarm: true,
        ..Config::default()
    });
    let file = job_file("alarm-connect", &zigzag(10));
    let a = args(&emu, &file);
    let (r, _) = run(&a);
    let err = r.expect_err("refuses");
    assert!(matches!(err, GrblError::AlarmAtConnect { .. }), "{err:?}");
    assert!(err.to_string().contains("$H") && err.to_string().contains("$X"));
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::Alarm);
    assert!(emu.lines().is_empty(), "nothing sent");
    assert!(emu.shared().received.is_empty(), "no $X sent on its own");
}

#[test]
fn unlock_on_request_then_stream() {
    let emu = Emulator::start(Config {
        start_in_alarm: true,
        ..Config::default()
    });
    let file = job_file("unlock", &zigzag(50));
    let mut a = args(&emu, &file);
    a.unlock = true;
    let (r, events) = run(&a);
    r.expect("streams after $X");
    assert_eq!(emu.shared().received[0].text, "$X");
    assert!(events.iter().any(|e| e.contains("Unlocked")), "{events:?}");
    assert_eq!(emu.lines(), file_blocks(&a));
}

#[test]
fn banner_on_open_needs_no_reset() {
    let emu = Emulator::start(Config::default());
    let link = Link::open(&emu.path, 115200).expect("open");
    emu.boot();
    let settings = Settings {
        banner_timeout: Duration::from_secs(5),
        ..Settings::default()
    };
    let s = Streamer::connect(link, settings, &mut ()).expect("connects");
    assert_eq!(s.version(), "1.1h");
    assert_eq!(emu.shared().resets, 0);
}

#[test]
fn stale_banner_is_flushed_and_grbl_reset() {
    // The board printed its banner long before pfcam opened the port (and GRBL may
    // have done anything since): that banner is not an answer to this connection.
    let emu = Emulator::start(Config::default());
    emu.wait_for("the boot banner", |s| s.banners >= 1);
    std::thread::sleep(Duration::from_millis(200));
    let file = job_file("stale", &zigzag(20));
    let (r, events) = run(&args(&emu, &file));
    r.expect("streams after a fresh banner");
    let s = emu.shared();
    assert_eq!(
        s.resets, 1,
        "the stale banner was flushed, so GRBL was soft-reset"
    );
    assert_eq!(s.banners, 2);
    assert_eq!(s.realtime.first().map(|r| r.0), Some(SOFT_RESET));
    assert!(events.iter().any(|e| e.contains("1.1h")), "{events:?}");
}

#[test]
fn feed_hold_and_resume() {
    let emu = Emulator::start(Config {
        speedup: 100.0,
        decel: Duration::from_millis(100),
        ..Config::default()
    });
    let file = job_file("hold", &zigzag(1500));
    let a = args(&emu, &file);
    let expected = file_blocks(&a);
    let (op, events, done) = spawn(a);
    emu.wait_for("500 lines", |s| s.received.len() >= 500);
    op.send(OperatorCommand::Hold).expect("send");
    wait_event(&events, "HoldRequested");
    // Resume asked while still decelerating: must wait for Hold:0.
    op.send(OperatorCommand::Resume).expect("send");
    wait_event(&events, "Resumed");
    let r = outcome(&done).expect("completes after resume");
    assert_eq!(r.acked, expected.len());
    assert_eq!(emu.lines(), expected);
    let s = emu.shared();
    assert_eq!(s.ignored_resumes, 0, "`~` sent only after Hold:0");
    let rt: Vec<u8> = s.realtime.iter().map(|r| r.0).collect();
    assert!(rt.ends_with(b"!~"), "{rt:?}");
    drop(s);
    assert_no_overflow(&emu);
}

#[test]
fn typed_overrides_reach_grbl_as_realtime_bytes() {
    use stream::keys::typed_command;
    let emu = Emulator::start(Config {
        speedup: 50.0,
        ..Config::default()
    });
    let file = job_file("overrides", &zigzag(600));
    let a = args(&emu, &file);
    let expected = file_blocks(&a);
    let (op, _events, done) = spawn(a);
    emu.wait_for("100 lines", |s| s.received.len() >= 100);
    // What the keyboard reader gets, through the same channel as hold/resume.
    let typed = ["f+", "f+", "F-1", "s-", "s -1", "r25", "r50"];
    for t in typed {
        op.send(typed_command(t).expect(t)).expect("send");
    }
    emu.wait_for("the overrides", |s| s.overrides == [119, 50, 89]);
    let report = outcome(&done).expect("completes");
    assert_eq!(report.acked, expected.len());
    assert_eq!(emu.lines(), expected, "the job is unchanged");
    let s = emu.shared();
    // (A soft reset at connect may come first: the boot banner can be stale.)
    let bytes: Vec<u8> = s
        .realtime
        .iter()
        .map(|r| r.0)
        .filter(|&b| b != SOFT_RESET)
        .collect();
    assert_eq!(bytes, [0x91, 0x91, 0x94, 0x9B, 0x9D, 0x97, 0x96]);
    drop(s);
    assert_no_overflow(&emu);
}

#[test]
fn hold_then_abort_resets_and_reports_last_line() {
    let emu = Emulator::start(Config {
        speedup: 50.0,
        ..Config::default()
    });
    let file = job_file("abort", &zigzag(1500));
    let a = args(&emu, &file);
    let program = Program::parse(&std::fs::read_to_string(&file).expect("read"));
    let (op, events, done) = spawn(a);
    emu.wait_for("300 lines", |s| s.received.len() >= 300);
    op.send(OperatorCommand::Hold).expect("send");
    wait_event(&events, "HoldComplete");
    let lines_at_hold = emu.shared().received.len();
    op.send(OperatorCommand::Abort).expect("send");
    let err = outcome(&done).expect_err("aborted");
    let GrblError::Aborted {
        by,
        last_acked,
        resume_from,
    } = err
    else {
        panic!("unexpected {err:?}");
    };
    assert_eq!(by, "aborted by the operator");
    let last = last_acked.expect("acknowledged lines");
    // Up to 15 acknowledged moves were still in the planner when the hold stopped.
    let resume = resume_from.expect("resume point");
    assert!(
        resume <= last && resume + 15 >= last,
        "resume {resume}, last {last}"
    );
    let s = emu.shared();
    // The last acknowledged line is the last line the emulator accepted.
    let accepted = s
        .received
        .iter()
        .rev()
        .find(|r| r.error.is_none())
        .expect("accepted");
    assert_eq!(program.lines[last - 1].block, accepted.text);
    assert_eq!(
        s.received.len(),
        lines_at_hold,
        "no line read after the hold"
    );
    assert!(!s.spindle_on, "soft reset stops the spindle");
    assert_eq!(s.realtime.last().map(|r| r.0), Some(SOFT_RESET));
    assert_eq!(
        s.state, "Idle",
        "GRBL 1.1h resets from Hold:0 to Idle, without an alarm"
    );
    drop(s);
    assert_eq!(
        ExitStatus::of(&Err(GrblError::Aborted {
            by: "aborted by the operator",
            last_acked,
            resume_from
        })),
        ExitStatus::Aborted
    );
}

#[test]
fn reset_before_the_hold_completes_raises_alarm_3_and_is_reported() {
    // A hold that takes longer than pfcam waits: the reset comes while GRBL is
    // still decelerating (Hold:1), which GRBL 1.1h flags with ALARM:3.
    let emu = Emulator::start(Config {
        speedup: 20.0,
        decel: Duration::from_secs(3),
        ..Config::default()
    });
    let file = job_file("abort-decel", &zigzag(500));
    let a = args(&emu, &file);
    let (_, blocks) = job_blocks(&a).expect("job");
    let link = Link::open(&emu.path, 115200).expect("open");
    let settings = Settings {
        hold_timeout: Duration::from_millis(200),
        banner_timeout: Duration::from_millis(300),
        ..a.settings()
    };
    let (op, rx) = mpsc::channel();
    let (ev_tx, events) = mpsc::channel();
    let worker = std::thread::spawn(move || {
        let mut rec = Recorder {
            events: Vec::new(),
            tx: Some(ev_tx),
        };
        let mut s = Streamer::connect(link, settings, &mut rec)?;
        s.stream(&blocks, &rx, &mut rec)
    });
    emu.wait_for("100 lines", |s| s.received.len() >= 100);
    op.send(OperatorCommand::Abort).expect("send");
    wait_event(&events, "ALARM:3");
    let r = worker.join().expect("streamer thread");
    assert!(matches!(r, Err(GrblError::Aborted { .. })), "{r:?}");
    let s = emu.shared();
    assert_eq!(s.state, "Alarm", "reset while decelerating");
    assert!(!s.spindle_on);
}

/// Runs `pfcam stream` as a process (stdin not a terminal) against `emu`, sends
/// it `signal` mid-job, and returns its exit code and stderr.
fn signalled_stream(emu: &Emulator, file: &Path, signal: &str) -> (Option<i32>, String) {
    use std::io::Read;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_pfcam"))
        .arg("stream")
        .arg(file)
        .args(["--port", &emu.path, "--connect-timeout", "0.3"])
        .args(["--status-hz", "50", "--response-timeout", "3"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run pfcam");
    emu.wait_for("100 lines", |s| s.received.len() >= 100);
    assert!(emu.shared().spindle_on, "cutting when the signal comes");
    let sent = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .expect("kill");
    assert!(sent.success());
    let deadline = std::time::Instant::now() + Duration::from_secs(15);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("pfcam did not exit after SIG{signal}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut stderr = String::new();
    if let Some(mut err) = child.stderr.take() {
        let _ = err.read_to_string(&mut stderr);
    }
    (status.code(), stderr)
}

#[test]
fn sigterm_sighup_and_unattended_sigint_hold_reset_and_exit() {
    for signal in ["TERM", "HUP", "INT"] {
        let emu = Emulator::start(Config {
            speedup: 20.0,
            ..Config::default()
        });
        let file = job_file(&format!("signal-{signal}"), &zigzag(2000));
        let (code, stderr) = signalled_stream(&emu, &file, signal);
        assert_eq!(
            code,
            Some(ExitStatus::Aborted as i32),
            "SIG{signal}: {stderr}"
        );
        assert!(
            stderr.contains("aborted") && stderr.contains(&format!("SIG{signal}")),
            "the message names the signal: {stderr}"
        );
        let s = emu.shared();
        let rt: Vec<u8> = s.realtime.iter().map(|r| r.0).collect();
        assert!(
            rt.ends_with(&[FEED_HOLD, SOFT_RESET]),
            "SIG{signal}: hold, then reset: {rt:?}"
        );
        assert!(!s.spindle_on, "SIG{signal}: spindle stopped");
        assert_eq!(s.state, "Idle", "SIG{signal}: reset from Hold:0");
    }
}

#[test]
fn check_mode_reports_every_error_without_moving() {
    let emu = Emulator::start(Config::default());
    let file = job_file("check", &with_errors());
    let mut a = args(&emu, &file);
    a.check = true;
    let (r, _) = run(&a);
    let err = r.expect_err("errors found");
    let GrblError::CheckFailed { faults } = &err else {
        panic!("unexpected {err:?}");
    };
    let lines: Vec<usize> = faults.iter().map(|f| f.line).collect();
    assert_eq!(lines, [50, 120]);
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::GrblError);
    let s = emu.shared();
    assert!(!s.moved, "check mode moves nothing");
    let dollar: Vec<&str> = s
        .received
        .iter()
        .filter(|r| r.text.starts_with('$'))
        .map(|r| r.text.as_str())
        .collect();
    assert_eq!(dollar, ["$C", "$C"]);
    assert_eq!(s.state, "Idle", "out of check mode");
}

#[test]
fn check_first_refuses_to_start_on_errors_and_streams_when_clean() {
    let emu = Emulator::start(Config::default());
    let bad = job_file("check-first-bad", &with_errors());
    let mut a = args(&emu, &bad);
    a.check_first = true;
    let (r, _) = run(&a);
    assert!(matches!(r, Err(GrblError::CheckFailed { .. })), "{r:?}");
    assert!(emu.lines().is_empty(), "nothing streamed");
    assert!(!emu.shared().moved);
    drop(emu);

    let emu = Emulator::start(Config::default());
    let good = job_file("check-first-good", &zigzag(300));
    let mut a = args(&emu, &good);
    a.check_first = true;
    let (r, _) = run(&a);
    r.expect("clean file streams");
    let s = emu.shared();
    let checked = s.received.iter().filter(|r| r.check_mode).count();
    assert_eq!(
        checked,
        file_blocks(&a).len() + 1,
        "all lines and the closing $C"
    );
    drop(s);
    assert_eq!(emu.lines(), file_blocks(&a));
    assert!(emu.shared().moved);
}

#[test]
fn from_line_restores_the_modal_state() {
    let text = "G21 G90 G17\n\
                G0 Z10\n\
                M4 S9000\n\
                M7\n\
                G0 X5 Y5\n\
                G1 Z-2 F250\n\
                G1 X15 Y5\n\
                G20\n\
                G1 X1 Y1 F20\n\
                G91\n\
                G1 X0.1 Y0.2\n\
                G1 X0.1 Y0.2\n\
                G90 G21\n\
                G1 X30 Y30 F400\n\
                G0 Z10\n\
                M5 M9\n";
    for resume_at in [7, 11, 12, 14] {
        let emu = Emulator::start(Config::default());
        let file = job_file(&format!("resume-{resume_at}"), text);
        let mut a = args(&emu, &file);
        a.from_line = Some(resume_at);
        let program = Program::parse(text);
        let expected = program.state_before(resume_at).expect("state");
        let (r, _) = run(&a);
        r.expect("resumed job completes");
        let s = emu.shared();
        let first = &program.lines[resume_at - 1].block;
        let at = s
            .received
            .iter()
            .position(|r| &r.text == first)
            .expect("resume line sent");
        let got = &s.received[at].state_before;
        assert_eq!(got.units, expected.units, "line {resume_at}");
        assert_eq!(got.distance, expected.distance);
        assert_eq!(got.plane, expected.plane);
        assert_eq!(got.wcs, expected.wcs);
        assert_eq!(got.feed, expected.feed);
        assert_eq!(got.spindle, expected.spindle);
        assert_eq!(got.spindle_speed, expected.spindle_speed);
        assert_eq!((got.mist, got.flood), (expected.mist, expected.flood));
        assert_eq!(got.motion, Motion::Linear);
        for i in 0..3 {
            let (g, e) = (
                got.position[i].expect("known"),
                expected.position[i].expect("known"),
            );
            assert!((g - e).abs() < 1e-3, "axis {i}: {g} vs {e}");
        }
        // Only pfcam's preamble comes before the resume line, and every move in it
        // that changes X/Y happens at safe Z (10 mm).
        let preamble: Vec<String> = job_blocks(&a)
            .expect("job")
            .1
            .into_iter()
            .filter(|b| b.line == 0)
            .map(|b| b.text)
            .collect();
        let before: Vec<&String> = s.received[..at].iter().map(|r| &r.text).collect();
        assert_eq!(before, preamble.iter().collect::<Vec<_>>());
        for w in s.received[..at].windows(2) {
            let (p0, p1) = (w[0].state_before.position, w[1].state_before.position);
            if p0[0] != p1[0] || p0[1] != p1[1] {
                assert!(
                    p0[2].unwrap_or(0.0) >= 10.0 - 1e-9 && p1[2].unwrap_or(0.0) >= 10.0 - 1e-9,
                    "XY move below safe Z: {}",
                    w[0].text
                );
            }
        }
        drop(s);
        assert_no_overflow(&emu);
    }
}

#[test]
fn from_line_plunges_at_the_programs_plunge_feed() {
    // zigzag: `G1 Z-0.500 F300` plunges, the cuts run at F800.
    let emu = Emulator::start(Config::default());
    let file = job_file("resume-plunge", &zigzag(100));
    let mut a = args(&emu, &file);
    let resume_at = 60;
    a.from_line = Some(resume_at);
    let (r, _) = run(&a);
    r.expect("resumed job completes");
    let program = Program::parse(&zigzag(100));
    let s = emu.shared();
    let at = s
        .received
        .iter()
        .position(|r| r.text == program.lines[resume_at - 1].block)
        .expect("resume line sent");
    // The preamble's move down to the resume point: the last Z-only feed move.
    let plunge = s.received[..at]
        .iter()
        .rposition(|r| r.text.starts_with("G1Z"))
        .expect("a plunge in the preamble");
    let feed_after = |i: usize| s.received[i + 1].state_before.feed;
    assert_eq!(
        feed_after(plunge),
        Some(300.0),
        "{}",
        s.received[plunge].text
    );
    assert!(
        s.received[plunge].state_before.position[2]
            > s.received[plunge + 1].state_before.position[2],
        "it goes down"
    );
    // ... and the program continues at its cutting feed.
    assert_eq!(s.received[at].state_before.feed, Some(800.0));
}

#[test]
fn from_line_refuses_when_the_position_is_unknown() {
    let file = job_file("resume-bad", "G0 Z5\nG28\nG1 X1 F100\n");
    let mut a = StreamArgs::new(file, "/nonexistent/port");
    a.from_line = Some(3);
    let (r, _) = run(&a);
    let err = r.expect_err("refused");
    assert!(err.to_string().contains("not known"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::BadInput);
}

#[test]
fn silent_port_times_out_with_a_clear_message() {
    let emu = Emulator::start(Config {
        personality: Personality::Silent,
        ..Config::default()
    });
    let file = job_file("silent", &zigzag(10));
    let (r, _) = run(&args(&emu, &file));
    let err = r.expect_err("no GRBL");
    assert!(matches!(err, GrblError::NoGrbl { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("no GRBL answered") && msg.contains("nothing was received"),
        "{msg}"
    );
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::Connection);
}

#[test]
fn noisy_port_is_not_taken_for_grbl() {
    let emu = Emulator::start(Config {
        personality: Personality::Noise,
        ..Config::default()
    });
    let file = job_file("noise", &zigzag(10));
    let (r, _) = run(&args(&emu, &file));
    let err = r.expect_err("no GRBL");
    let msg = err.to_string();
    assert!(
        msg.contains("received instead") && msg.contains("hello"),
        "{msg}"
    );
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::Connection);
}

#[test]
fn missing_port_is_a_connection_failure() {
    let file = job_file("noport", &zigzag(10));
    let (r, _) = run(&StreamArgs::new(file, "/dev/pfcam-no-such-port"));
    let err = r.expect_err("no port");
    assert!(err.to_string().contains("/dev/pfcam-no-such-port"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::Connection);
}

#[test]
fn port_that_disappears_mid_stream_ends_without_hanging() {
    let emu = Emulator::start(Config {
        die_after: Some(400),
        ..Config::default()
    });
    let file = job_file("dies", &zigzag(2000));
    let (_op, _events, done) = spawn(args(&emu, &file));
    let err = outcome(&done).expect_err("link lost");
    assert!(emu.shared().dead);
    let last = match &err {
        GrblError::LinkLost { last_acked, .. } | GrblError::Unresponsive { last_acked, .. } => {
            last_acked.expect("lines were acknowledged")
        }
        other => panic!("unexpected {other:?}"),
    };
    // The controller really answered the reported line. (Its last few `ok`s can
    // be lost with the link, so it may have answered a little more.)
    let program = Program::parse(&zigzag(2000));
    let s = emu.shared();
    let acked_text = &program.lines[last - 1].block;
    let at = s
        .received
        .iter()
        .position(|r| &r.text == acked_text)
        .expect("reported line was received");
    assert!(s.received.len() - at <= 20, "reported line is recent");
    drop(s);
    assert!(err.resume_from().is_some(), "a resume point is reported");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::LinkLost);
}

#[test]
fn overlong_line_is_refused_before_sending() {
    let emu = Emulator::start(Config::default());
    let long = format!("G21\nG1 X1 F100 Y2 Z{}\n", "1".repeat(90));
    let file = job_file("long", &long);
    let (r, _) = run(&args(&emu, &file));
    let err = r.expect_err("refused");
    assert!(err.to_string().contains("line 2"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::BadInput);
    assert!(emu.lines().is_empty());
}

#[test]
fn controller_that_hangs_is_detected_and_stopped() {
    let emu = Emulator::start(Config {
        freeze_after: Some(200),
        ..Config::default()
    });
    let file = job_file("freeze", &zigzag(1000));
    let mut a = args(&emu, &file);
    a.response_timeout = 0.5;
    let (_op, _events, done) = spawn(a);
    let err = outcome(&done).expect_err("unresponsive");
    let GrblError::Unresponsive { last_acked, .. } = &err else {
        panic!("unexpected {err:?}");
    };
    // The last acknowledged line is the last one the controller answered.
    let program = Program::parse(&zigzag(1000));
    let last = last_acked.expect("lines were acknowledged");
    let answered = emu.shared().received.last().map(|r| r.text.clone());
    assert_eq!(Some(program.lines[last - 1].block.clone()), answered);
    assert!(err.to_string().contains("stopped answering"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::LinkLost);
}

#[test]
fn lost_ok_is_detected_as_a_stall_not_a_hang() {
    // GRBL runs every line but one `ok` never arrives: it ends idle with empty
    // buffers (`Bf:15,128`) while the sender still counts a line in flight, and
    // its status reports keep coming.
    let emu = Emulator::start(Config {
        drop_ok: Some(120),
        ..Config::default()
    });
    let file = job_file("stall", &zigzag(300));
    let mut a = args(&emu, &file);
    a.response_timeout = 0.5;
    let (_op, _events, done) = spawn(a.clone());
    let err = outcome(&done).expect_err("stall detected");
    let GrblError::Stalled {
        unacked,
        seconds,
        last_acked,
        resume_from,
    } = &err
    else {
        panic!("unexpected {err:?}");
    };
    assert_eq!(*unacked, 1);
    assert!(*seconds >= 0.5 && *seconds < 2.0, "{seconds}");
    let total = file_blocks(&a).len();
    // Every line ran; the sender can only know all but the last were answered.
    assert_eq!(emu.lines().len(), total);
    assert_eq!(emu.shared().dropped_oks, 1);
    let last = last_acked.expect("acked");
    assert_eq!(*resume_from, Some(last + 1));
    assert!(err.to_string().contains("never acknowledged"), "{err}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::LinkLost);
    let s = emu.shared();
    let rt: Vec<u8> = s.realtime.iter().map(|r| r.0).collect();
    assert!(rt.ends_with(&[FEED_HOLD, SOFT_RESET]), "{rt:?}");
    assert!(!s.spindle_on);
}

#[test]
fn lost_ok_in_check_mode_is_a_stall_too() {
    let emu = Emulator::start(Config {
        drop_ok: Some(40),
        ..Config::default()
    });
    let file = job_file("stall-check", &zigzag(100));
    let mut a = args(&emu, &file);
    a.check = true;
    a.response_timeout = 0.5;
    let (_op, _events, done) = spawn(a);
    let err = outcome(&done).expect_err("stall detected");
    assert!(
        matches!(err, GrblError::Stalled { unacked: 1, .. }),
        "{err:?}"
    );
    assert!(!emu.shared().moved, "check mode moves nothing");
}

#[test]
fn controller_reset_mid_job_stops_the_stream() {
    let emu = Emulator::start(Config {
        reboot_after: Some(150),
        ..Config::default()
    });
    let file = job_file("reboot", &zigzag(1000));
    let (r, _) = run(&args(&emu, &file));
    let err = r.expect_err("reset detected");
    assert!(matches!(err, GrblError::UnexpectedReset { .. }), "{err:?}");
    assert_eq!(ExitStatus::of(&Err(err)), ExitStatus::LinkLost);
    // Nothing is sent into a freshly reset controller (its lines would run
    // without the job's modal state).
    let s = emu.shared();
    let at = s.rebooted_at.expect("rebooted");
    let late: usize = s.received[at..].iter().map(|r| r.text.len() + 1).sum();
    assert!(late <= 128, "{late} bytes sent after the reset");
}

#[test]
fn stream_command_exit_codes() {
    let emu = Emulator::start(Config::default());
    let file = job_file("cmd-ok", &zigzag(100));
    let code = stream::stream_command(&args(&emu, &file));
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::from(0))
    );
    drop(emu);

    let emu = Emulator::start(Config::default());
    let file = job_file("cmd-err", &with_errors());
    let mut a = args(&emu, &file);
    a.continue_on_error = true;
    let code = stream::stream_command(&a);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::from(4))
    );
    drop(emu);

    let emu = Emulator::start(Config {
        alarm_after: Some((40, 2)),
        ..Config::default()
    });
    let code = stream::stream_command(&args(&emu, &file));
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::from(5))
    );
    drop(emu);

    let emu = Emulator::start(Config::default());
    let code = stream::stream_command(&args(&emu, &file));
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::from(4))
    );
}

#[test]
fn smaller_receive_buffer_is_respected() {
    let emu = Emulator::start(Config {
        rx_buffer: 64,
        ..Config::default()
    });
    let file = job_file("rx64", &zigzag(500));
    let mut a = args(&emu, &file);
    a.rx_buffer = 64;
    let (r, _) = run(&a);
    let report = r.expect("completes");
    assert!(report.max_in_flight <= 64, "{}", report.max_in_flight);
    let s = emu.shared();
    assert!(s.overflow.is_none(), "{:?}", s.overflow);
    assert!(s.max_rx <= 64);
    drop(s);
    assert_eq!(emu.lines(), file_blocks(&a));
}

/// Keeps every status report.
struct Reports(Vec<StatusReport>);

impl Observer for Reports {
    fn event(&mut self, event: Event<'_>) {
        if let Event::Status(r) = event {
            self.0.push(r.clone());
        }
    }
}

fn reports_of(config: Config, name: &str) -> Vec<StatusReport> {
    let emu = Emulator::start(config);
    let file = job_file(name, &zigzag(300));
    let (_tx, rx) = mpsc::channel();
    let mut obs = Reports(Vec::new());
    run_stream(&args(&emu, &file), &rx, &mut obs).expect("completes");
    obs.0
}

#[test]
fn work_position_uses_the_wco_grbl_reported_earlier() {
    // G54 at machine (-200, -100, -30); GRBL names it in every 7th report only.
    let wco = [-200.0, -100.0, -30.0];
    let reports = reports_of(
        Config {
            wco,
            wco_every: 7,
            speedup: 100.0,
            ..Config::default()
        },
        "wco",
    );
    assert!(reports[0].wco.is_some(), "GRBL's first report has the WCO");
    let without = reports.iter().filter(|r| r.wco.is_none()).count();
    assert!(
        without * 2 > reports.len(),
        "{without} of {}",
        reports.len()
    );
    let mut offset = WorkOffset::default();
    for r in &reports {
        let m = r.mpos.expect("MPos");
        let Some(Position::Work(p)) = offset.update(r) else {
            panic!("no work position for {r:?}");
        };
        for i in 0..3 {
            assert!((p[i] - (m[i] - wco[i])).abs() < 1e-9, "{r:?}: {p:?}");
        }
    }
    // The job ends at work Z 5 (machine Z -25).
    let last = offset.update(reports.last().expect("reports"));
    assert!(
        last.is_some_and(|p| p.to_string().starts_with("WPos") && p.to_string().contains("Z5.000")),
        "{last:?}"
    );
    // Before any WCO, MPos is shown as what it is.
    let m = StatusReport::parse("<Idle|MPos:-200.000,-100.000,-25.000>").expect("report");
    let shown = WorkOffset::default()
        .update(&m)
        .expect("position")
        .to_string();
    assert!(
        shown.starts_with("MPos") && shown.contains("not reported"),
        "{shown}"
    );
}

#[test]
fn work_position_reported_directly_is_used_as_is() {
    let reports = reports_of(
        Config {
            wco: [-200.0, -100.0, -30.0],
            report_wpos: true,
            ..Config::default()
        },
        "wpos",
    );
    let mut offset = WorkOffset::default();
    for r in &reports {
        assert!(r.mpos.is_none());
        assert_eq!(offset.update(r), r.wpos.map(Position::Work));
    }
    let last = reports.last().and_then(|r| r.wpos).expect("WPos");
    assert!((last[2] - 5.0).abs() < 1e-9, "{last:?}");
}

#[test]
fn push_messages_are_shown_not_counted_as_acks() {
    let emu = Emulator::start(Config::default());
    let mut text = String::from("G21 G90\nG0 Z2\nG38.2 Z-5 F50\nG0 Z2\n");
    for i in 0..100 {
        text.push_str(&format!("G1 X{i} F300\n"));
    }
    let file = job_file("probe", &text);
    let a = args(&emu, &file);
    let (r, events) = run(&a);
    let report = r.expect("completes");
    assert!(events.iter().any(|e| e.contains("[PRB:")), "{events:?}");
    assert_eq!(report.acked, 104);
    assert_eq!(emu.lines(), file_blocks(&a));
}

/// The lines docs/grbl.md's throughput table gives for the emulator `row`.
fn doc_lines(row: &str) -> Option<usize> {
    let doc = doc_figures::read("docs/grbl.md");
    doc_figures::table_row(&doc, "docs/grbl.md", row)[1]
        .parse()
        .ok()
}

/// docs/grbl.md counts the tests of this file.
#[test]
fn docs_count_the_tests_of_this_file() {
    let me = std::fs::read_to_string(file!()).expect("tests/grbl/main.rs");
    let tests = me.lines().filter(|l| l.trim() == "#[test]").count();
    let doc = doc_figures::read("docs/grbl.md");
    let stated = doc_figures::number_after(
        &doc,
        "docs/grbl.md",
        "`cargo test --release --test grbl` runs",
    );
    assert_eq!(
        stated.parse().ok(),
        Some(tests),
        "docs/grbl.md's test count"
    );
}
