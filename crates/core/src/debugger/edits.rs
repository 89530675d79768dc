//! User edits: changing a location's value or bit, switching inputs, forcing bits. Each is
//! checked against the location first and becomes part of the replayable timeline.

use super::history::Change;
use super::{Debugger, Event};
use crate::machine::{Loc, value};

/// Why a typed value was not stored.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EditError {
    #[error("there is no location named '{0}'")]
    Unknown(String),
    #[error(transparent)]
    Value(#[from] crate::machine::value::ValueError),
    #[error(transparent)]
    Refused(#[from] crate::machine::WriteError),
    #[error("fix the program's errors first: edits apply to a running program")]
    NotAssembled,
    #[error("{name} has {width} bit(s): there is no bit {bit}")]
    NoSuchBit { name: String, bit: u8, width: u8 },
    #[error("the program has {0}: step back or reset to change its state")]
    Stopped(&'static str),
}

impl Change {
    /// Whether this change can be made to the location `info` describes: it is writable, a
    /// value fits its width, a bit is one of its bits. Checked before any edit is recorded, so
    /// the timeline only ever holds edits that apply.
    pub fn check(self, info: &crate::machine::LocInfo) -> Result<(), EditError> {
        if !info.editable {
            return Err(crate::machine::WriteError::ReadOnly(info.name.clone()).into());
        }
        match self {
            Change::Set(value) if info.width < 64 && value >> info.width != 0 => {
                Err(crate::machine::WriteError::TooWide {
                    name: info.name.clone(),
                    value,
                    width: info.width,
                }
                .into())
            }
            Change::Bit { bit, .. } if bit >= info.width => Err(EditError::NoSuchBit {
                name: info.name.clone(),
                bit,
                width: info.width,
            }),
            Change::Force(_) if info.width != 1 => {
                Err(crate::machine::WriteError::NotForceable(info.name.clone()).into())
            }
            _ => Ok(()),
        }
    }
}

impl Debugger {
    // ---- edits -----------------------------------------------------------------------------

    /// Change a location now; the edit becomes part of the timeline. A refused edit changes
    /// nothing.
    pub fn edit(&mut self, loc: Loc, change: Change) -> Result<(), EditError> {
        if self.has_errors() {
            return Err(EditError::NotAssembled);
        }
        // A stopped run has no future for an edit to change, and an edit recorded at the
        // stop's position would replay before the instruction that stopped it: refused.
        let state = self.machine().run_state();
        if !state.is_live() {
            return Err(EditError::Stopped(state.label()));
        }
        let info = self
            .machine()
            .info(loc)
            .ok_or(crate::machine::WriteError::NoSuchLocation)?;
        change.check(&info)?;
        let now = self.machine().read(loc);
        let unchanged = match change {
            Change::Set(v) => v == now,
            Change::Bit { bit, on } => (now >> bit & 1 == 1) == on,
            Change::Force(level) => self.machine().forced(loc) == level,
        };
        if unchanged {
            // Writing what is already there changes nothing: no event, the future stays.
            return Ok(());
        }
        let at = self.pos();
        if self.engine.edit(loc, change)? {
            self.event = Some(Event::FutureDiscarded(at.tick));
            self.checker.borrow_mut().forget_log_after(at);
        }
        Ok(())
    }

    /// Store a raw value in a location.
    pub fn set_value(&mut self, loc: Loc, value: u64) -> Result<(), EditError> {
        self.edit(loc, Change::Set(value))
    }

    /// Parse what the user typed for the location named `name` and store it. On error nothing
    /// changes.
    pub fn set_text(&mut self, name: &str, text: &str) -> Result<u64, EditError> {
        let loc = self
            .find(name)
            .ok_or_else(|| EditError::Unknown(name.to_string()))?;
        self.set_loc_text(loc, text)
    }

    /// Parse what the user typed for `loc` (at its width) and store it.
    pub fn set_loc_text(&mut self, loc: Loc, text: &str) -> Result<u64, EditError> {
        let info = self
            .machine()
            .info(loc)
            .ok_or_else(|| EditError::Unknown(format!("{loc:?}")))?;
        let value = value::parse_value(text, info.width).map_err(EditError::Value)?;
        self.set_value(loc, value)?;
        Ok(value)
    }

    /// Flip one bit of a location.
    pub fn toggle_bit(&mut self, loc: Loc, bit: u8) -> Result<(), EditError> {
        // A bit past 63 reads as clear; `edit` refuses it (and any past the width).
        let on = self
            .machine()
            .read(loc)
            .checked_shr(u32::from(bit))
            .unwrap_or(0)
            & 1
            == 0;
        self.edit(loc, Change::Bit { bit, on })
    }

    /// Set one bit of a location.
    pub fn set_bit(&mut self, loc: Loc, bit: u8, on: bool) -> Result<(), EditError> {
        self.edit(loc, Change::Bit { bit, on })
    }

    /// Switch an input (any 1-bit location) high or low; nothing is recorded when it already
    /// is.
    pub fn set_input(&mut self, loc: Loc, high: bool) -> Result<(), EditError> {
        if (self.machine().read(loc) != 0) == high {
            return Ok(());
        }
        self.set_value(loc, u64::from(high))
    }

    /// Force a bit ON or OFF (`Some`) or release it (`None`) from now on: a user event like an
    /// edit, so time travel replays it and sessions keep it.
    pub fn force(&mut self, loc: Loc, level: Option<bool>) -> Result<(), EditError> {
        self.edit(loc, Change::Force(level))
    }

    /// Release every force now.
    pub fn release_all_forces(&mut self) -> Result<(), EditError> {
        for (loc, _) in self.machine().forces() {
            self.force(loc, None)?;
        }
        Ok(())
    }
}
