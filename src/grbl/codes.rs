//! What GRBL 1.1's `error:N` and `ALARM:N` numbers mean, in pfcam's words.
//!
//! Numbers and meanings from GRBL's `doc/csv/error_codes_en_US.csv` and
//! `alarm_codes_en_US.csv`.

/// Meaning of `error:N`.
pub fn error_meaning(code: u8) -> &'static str {
    match code {
        1 => "a word has no letter (G-code words are a letter and a number)",
        2 => "a number is missing or malformed",
        3 => "GRBL does not know this `$` command",
        4 => "a value that must be positive is negative",
        5 => "homing is not enabled in the settings ($22)",
        6 => "step pulse time must be at least 3 microseconds",
        7 => "GRBL could not read its EEPROM and restored defaults",
        8 => "this `$` command is only allowed while GRBL is idle",
        9 => "G-code is locked out while in alarm or jog state",
        10 => "soft limits need homing enabled",
        11 => "the line is longer than GRBL's line buffer and was not run",
        12 => "the setting would make the step rate exceed GRBL's maximum",
        13 => "the safety door is open",
        14 => "the startup or build-info line is too long to store",
        15 => "the jog target is outside the machine travel",
        16 => "the jog command is malformed or contains a forbidden G-code",
        17 => "laser mode needs PWM spindle output",
        20 => "unsupported or invalid G-code command in the block",
        21 => "two commands of the same modal group in one block",
        22 => "feed rate not set (no F word before a feed move)",
        23 => "the command needs an integer value",
        24 => "two commands in the block need axis words",
        25 => "a word is repeated in the block",
        26 => "the command needs axis words and the block has none",
        27 => "the line number (N) is invalid",
        28 => "the command is missing a required value word",
        29 => "G59.1, G59.2 and G59.3 are not supported",
        30 => "G53 is only allowed with G0 and G1",
        31 => "axis words in a block where no command uses them",
        32 => "G2/G3 arcs need at least one axis word in the arc plane",
        33 => "the motion target is invalid",
        34 => "the arc radius is invalid",
        35 => "G2/G3 arcs need at least one offset word (I/J/K) in the plane",
        36 => "value words in the block that no command uses",
        37 => "G43.1 offset is not on the configured tool-length axis",
        38 => "tool number above the maximum",
        _ => "unknown error number (not in GRBL 1.1's table)",
    }
}

/// Meaning of `ALARM:N`, with the advice for the operator.
pub fn alarm_meaning(code: u8) -> &'static str {
    match code {
        1 => {
            "hard limit switch hit; machine position is probably lost: home ($H) before continuing"
        }
        2 => "soft limit: a move would leave the machine travel; position is kept, $X unlocks",
        3 => "reset while moving; machine position is probably lost: home ($H) before continuing",
        4 => "probe fail: the probe was already triggered (or not) before the probe cycle",
        5 => "probe fail: the probe did not touch within the programmed travel",
        6 => "homing fail: the homing cycle was reset",
        7 => "homing fail: the safety door opened during homing",
        8 => "homing fail: pull-off did not clear the limit switch",
        9 => "homing fail: no limit switch found within the search distance",
        10 => "homing fail: the second switch of a dual axis did not trigger",
        _ => "unknown alarm number (not in GRBL 1.1's table)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_table_code_has_a_meaning() {
        for code in (1..=17).chain(20..=38) {
            assert!(!error_meaning(code).starts_with("unknown"), "error {code}");
        }
        for code in 1..=10 {
            assert!(!alarm_meaning(code).starts_with("unknown"), "alarm {code}");
        }
        assert!(error_meaning(99).starts_with("unknown"));
    }
}
