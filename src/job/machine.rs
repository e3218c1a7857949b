//! The machine: `[machine]` of a job, or a machine file with only that
//! table ([`load_machine`], for `pfcam check`), resolved to a [`Machine`] that
//! only the G-code writer, the time estimates and the checks read.

use super::load::{load_job, parse_error, read_bounded};
use super::{defaults, exact, invalid, limits, JobError};
use serde::Deserialize;
use std::path::Path;

/// Machine settings used by the G-code writer and the time estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    /// Rate assumed for rapid (G0) moves in time estimates, mm/min. GRBL's real
    /// rapid rate is its `$110`/`$111`/`$112` setting; pfcam cannot read it.
    pub rapid_rate: f64,
    /// Dwell after `M3` so the spindle reaches speed before the first cut, seconds
    /// (0 writes no `G4`).
    pub(crate) spindle_dwell: f64,
    /// Flood coolant: `M8` after the spindle starts, `M9` before it stops.
    pub(crate) coolant: bool,
    /// Travel of X, Y, Z in mm (GRBL's `$130`–`$132`): after homing, machine
    /// coordinates run from 0 down to −travel. Read only by `pfcam check`.
    pub travel: Option<[f64; 3]>,
    /// Machine position of the work origin (G54's offset as `$#` shows it,
    /// MPos − WPos), mm. With `travel`, `pfcam check` tests every move against the
    /// machine's limits; without it, only the program's size against the travel.
    pub work_offset: Option<[f64; 3]>,
    /// Longest estimated machining time of a program, hours: a job whose lower
    /// bound or whose program's estimate passes it stops with an error.
    pub(crate) max_hours: f64,
    /// Largest G-code file, MB (10⁶ bytes): a program that would be larger is
    /// not written.
    pub(crate) max_file_mb: f64,
}

impl Default for Machine {
    fn default() -> Self {
        Machine {
            rapid_rate: defaults::RAPID_RATE,
            spindle_dwell: defaults::SPINDLE_DWELL,
            travel: None,
            work_offset: None,
            coolant: defaults::COOLANT,
            max_hours: defaults::MAX_HOURS,
            max_file_mb: defaults::MAX_FILE_MB,
        }
    }
}

/// `[machine]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMachine {
    /// `rapid_rate`, mm/min
    pub(crate) rapid_rate: Option<f64>,
    /// `spindle_dwell`, s
    pub(crate) spindle_dwell: Option<f64>,
    /// `coolant`
    pub(crate) coolant: Option<bool>,
    /// `travel`, mm: [x, y, z]
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) travel: Option<[f64; 3]>,
    /// `work_offset`, mm: [x, y, z]
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) work_offset: Option<[f64; 3]>,
    /// `max_hours`, h
    pub(crate) max_hours: Option<f64>,
    /// `max_file_mb`, MB
    pub(crate) max_file_mb: Option<f64>,
}

impl RawMachine {
    /// Checks `[machine]` and applies its defaults.
    pub(crate) fn resolve(self) -> Result<Machine, JobError> {
        let m = self;
        let travel = match m.travel {
            None => None,
            Some(t) => {
                for (k, axis) in t.iter().zip(["x", "y", "z"]) {
                    limits::TRAVEL.check(&format!("machine.travel ({axis})"), *k)?;
                }
                Some(t)
            }
        };
        let work_offset = match m.work_offset {
            None => None,
            Some(o) => {
                if travel.is_none() {
                    return Err(invalid(
                        "machine.work_offset",
                        "needs machine.travel (the offset places the work origin inside it)",
                    ));
                }
                for v in o {
                    limits::WORK_OFFSET.check("machine.work_offset", v)?;
                }
                Some(o)
            }
        };
        Ok(Machine {
            rapid_rate: limits::RAPID_RATE.check(
                "machine.rapid_rate",
                m.rapid_rate.unwrap_or(defaults::RAPID_RATE),
            )?,
            spindle_dwell: limits::SPINDLE_DWELL.check(
                "machine.spindle_dwell",
                m.spindle_dwell.unwrap_or(defaults::SPINDLE_DWELL),
            )?,
            coolant: m.coolant.unwrap_or(defaults::COOLANT),
            travel,
            work_offset,
            max_hours: limits::MAX_HOURS.check(
                "machine.max_hours",
                m.max_hours.unwrap_or(defaults::MAX_HOURS),
            )?,
            max_file_mb: limits::MAX_FILE_MB.check(
                "machine.max_file_mb",
                m.max_file_mb.unwrap_or(defaults::MAX_FILE_MB),
            )?,
        })
    }
}

/// A file with only a `[machine]` table (see [`load_machine`]).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMachineFile {
    machine: Option<RawMachine>,
}

/// Where [`load_machine`] found the machine settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MachineSource {
    /// A whole job file: its `[machine]` table.
    Job,
    /// A machine file: a TOML file with only a `[machine]` table.
    MachineFile,
}

/// Reads `[machine]` from either a job file or a machine file (a TOML file whose
/// only table is `[machine]`), with the same keys and checks as in a job.
pub fn load_machine(path: &Path) -> Result<(Machine, MachineSource), JobError> {
    let text = read_bounded(path)?;
    let is_machine_file = match text.parse::<toml::Table>() {
        Ok(t) => t.keys().all(|k| k == "machine"),
        // Let the job reader report where the TOML is wrong.
        Err(_) => false,
    };
    if !is_machine_file {
        return Ok((load_job(path)?.machine, MachineSource::Job));
    }
    let raw: RawMachineFile =
        toml::from_str(&text).map_err(|e| parse_error(&text, e).in_file(path))?;
    Ok((
        raw.machine.unwrap_or_default().resolve()?,
        MachineSource::MachineFile,
    ))
}

#[cfg(test)]
mod tests {
    use crate::job::tests::{err_key, parse, with};

    #[test]
    fn machine_settings() {
        let j = parse(&with("machine", "rapid_rate = 3000\nspindle_dwell = 0")).unwrap();
        assert_eq!(j.machine.rapid_rate, 3000.0);
        assert_eq!(j.machine.spindle_dwell, 0.0);
        assert_eq!(
            err_key(&with("machine", "rapid_rate = 0")).0,
            "machine.rapid_rate"
        );
        assert_eq!(
            err_key(&with("machine", "spindle_dwell = -1")).0,
            "machine.spindle_dwell"
        );
        let j = parse(&with(
            "machine",
            "travel = [300, 200, 60]\nwork_offset = [-250.0, -150, -40]",
        ))
        .unwrap();
        assert_eq!(j.machine.travel, Some([300.0, 200.0, 60.0]));
        assert_eq!(j.machine.work_offset, Some([-250.0, -150.0, -40.0]));
        assert_eq!(
            err_key(&with("machine", "travel = [300, 0, 60]")).0,
            "machine.travel (y)"
        );
        assert_eq!(
            err_key(&with("machine", "work_offset = [0, 0, 0]")).0,
            "machine.work_offset"
        );
        let j = parse(&with("machine", "max_hours = 0.5\nmax_file_mb = 2")).unwrap();
        assert_eq!((j.machine.max_hours, j.machine.max_file_mb), (0.5, 2.0));
        for (bad, key) in [
            ("max_hours = 0", "machine.max_hours"),
            ("max_hours = 1001", "machine.max_hours"),
            ("max_file_mb = -1", "machine.max_file_mb"),
            ("max_file_mb = 10001", "machine.max_file_mb"),
        ] {
            assert_eq!(err_key(&with("machine", bad)).0, key, "{bad}");
        }
    }
}
