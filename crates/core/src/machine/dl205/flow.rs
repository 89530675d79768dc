//! Where execution goes: FOR/NEXT loops, subroutine calls and returns, master lines and
//! stages (SG, ISG, JMP) with the stage and block power they decide.

use super::program::{Bit, Kind, Op};
use super::{Dl205, Flow, Loop, StageChange, ZONES_AT_START};

impl Dl205 {
    /// A standalone instruction (spec §6.8, §6.10): where execution goes next.
    pub(super) fn standalone(&mut self, op: Op) -> Flow {
        match op {
            Op::Next(for_at) => match self.loop_state {
                Some(Loop { left, .. }) if left > 1 => {
                    self.loop_state = Some(Loop {
                        for_at,
                        left: left - 1,
                    });
                    Flow::To(for_at + 1)
                }
                _ => {
                    self.loop_state = None;
                    Flow::Next
                }
            },
            Op::Sbr(_) => {
                self.bstack.clear();
                self.level = 0;
                self.zones = ZONES_AT_START;
                self.stage_power = true;
                self.loop_state = None;
                self.update_block_power();
                Flow::Next
            }
            Op::Rt => match self.return_from_call() {
                Some(ret) => Flow::To(ret),
                // Only a call reaches a subroutine (checked at assembly): end the scan.
                None => Flow::EndScan,
            },
            Op::Mlr(n) => {
                self.level = n.min(7);
                self.update_block_power();
                Flow::Next
            }
            Op::Sg { stage, next, .. } => {
                self.level = 0;
                self.zones = ZONES_AT_START;
                let i = stage as usize;
                let on = self.s.get(i).copied().unwrap_or(false);
                let marked = self.stage_marks.get(i).copied().unwrap_or(false);
                let flow = if on {
                    self.stage_power = true;
                    self.stage_marks[i] = true;
                    Flow::Next
                } else if marked {
                    // One clean-up pass: outputs see no power, timers reset.
                    self.stage_power = false;
                    self.stage_marks[i] = false;
                    Flow::Next
                } else {
                    Flow::To(next)
                };
                self.update_block_power();
                flow
            }
            _ => Flow::Next,
        }
    }

    /// RT/RTC: the caller's state back; where to continue (None: no call in progress).
    pub(super) fn return_from_call(&mut self) -> Option<u32> {
        let frame = self.calls.pop()?;
        self.bstack = frame.bstack;
        self.rung_has_output = frame.rung_has_output;
        self.level = frame.level;
        self.zones = frame.zones;
        self.stage_power = frame.stage_power;
        self.loop_state = frame.loop_state;
        self.update_block_power();
        Some(frame.ret)
    }

    /// JMP: the enclosing stage off, the target on.
    pub(super) fn jump_stage(&mut self, own: u32, to: u32) {
        self.set_bit(
            Bit {
                kind: Kind::S,
                n: own,
            },
            false,
        );
        self.set_bit(
            Bit {
                kind: Kind::S,
                n: to,
            },
            true,
        );
    }

    /// Remember which instruction last changed stage bit `n`, and when (the Stages panel).
    pub(super) fn note_stage_change(&mut self, n: u32) {
        let change = StageChange {
            stage: n,
            line: self.pc_line_now(),
            at: crate::machine::Pos {
                tick: self.tick,
                step: self.step + 1,
            },
        };
        match self.stage_changes.iter_mut().find(|c| c.stage == n) {
            Some(c) => *c = change,
            None => self.stage_changes.push(change),
        }
    }

    pub(super) fn update_block_power(&mut self) {
        self.block_power = self.stage_power && self.zones[usize::from(self.level.min(7))];
    }
}
