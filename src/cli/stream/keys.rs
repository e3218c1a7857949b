//! Lines typed during a stream: resume or abort at the hold prompt, feed, rapid
//! and spindle overrides at any time (docs/grbl.md, "Overrides from the keyboard").

use std::io::{BufRead, IsTerminal};
use std::sync::mpsc::Sender;

use pfcam::grbl::protocol::Override;
use pfcam::grbl::OperatorCommand;

/// What a line typed during a stream asks for (case and spaces ignored):
/// `r`/`resume`, `a`/`abort` at the hold prompt; overrides at any time:
/// `f+`/`f-` feed ±10 %, `f+1`/`f-1` ±1 %, `f=` (or `f100`) back to 100 %;
/// `s+`, `s-`, `s+1`, `s-1`, `s=` (`s100`) the same for the spindle;
/// `r100`, `r50`, `r25` rapids. Anything else: `None`.
pub fn typed_command(line: &str) -> Option<OperatorCommand> {
    let key: String = line
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_lowercase();
    let o = match key.as_str() {
        "r" | "resume" => return Some(OperatorCommand::Resume),
        "a" | "abort" => return Some(OperatorCommand::Abort),
        "f=" | "f100" => Override::FeedReset,
        "f+" => Override::FeedUp10,
        "f-" => Override::FeedDown10,
        "f+1" => Override::FeedUp1,
        "f-1" => Override::FeedDown1,
        "r100" => Override::Rapid100,
        "r50" => Override::Rapid50,
        "r25" => Override::Rapid25,
        "s=" | "s100" => Override::SpindleReset,
        "s+" => Override::SpindleUp10,
        "s-" => Override::SpindleDown10,
        "s+1" => Override::SpindleUp1,
        "s-1" => Override::SpindleDown1,
        _ => return None,
    };
    Some(OperatorCommand::Override(o))
}

/// Reads typed commands ([`typed_command`]) from stdin.
pub fn spawn_prompt_reader(tx: Sender<OperatorCommand>) {
    if !std::io::stdin().is_terminal() {
        return;
    }
    let _ = std::thread::Builder::new()
        .name("hold-prompt".into())
        .spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { return };
                let Some(cmd) = typed_command(&line) else {
                    continue;
                };
                if tx.send(cmd).is_err() {
                    return;
                }
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_commands_map_to_grbl_override_bytes() {
        let byte = |t: &str| match typed_command(t) {
            Some(OperatorCommand::Override(o)) => Some(o.byte()),
            _ => None,
        };
        let keys = [
            "f=", "f+", "f-", "f+1", "f-1", "r100", "r50", "r25", "s=", "s+", "s-", "s+1", "s-1",
        ];
        let bytes: Vec<Option<u8>> = keys.iter().map(|k| byte(k)).collect();
        let want: Vec<Option<u8>> = (0x90..=0x97).chain(0x99..=0x9D).map(Some).collect();
        assert_eq!(bytes, want);
        assert_eq!(byte("f100"), Some(0x90));
        assert_eq!(byte("S100"), Some(0x99));
        assert_eq!(typed_command(" R "), Some(OperatorCommand::Resume));
        assert_eq!(typed_command("abort"), Some(OperatorCommand::Abort));
        assert_eq!(typed_command("f+2"), None);
        assert_eq!(typed_command(""), None);
    }
}
