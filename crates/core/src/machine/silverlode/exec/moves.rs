//! Moves and the motion model: a move command started, the zero point shifted, and the motion
//! phase of a tick.

use super::{Exec, Raise};
use crate::machine::silverlode::motion::FRAC;
use crate::machine::silverlode::program::{Cond, MoveKind};
use crate::machine::silverlode::{FaultKind, Outcome, SilverLode, isw, psw};
use crate::machine::{RunState, WaitReason};

impl SilverLode {
    pub(super) fn start_move(
        &mut self,
        kind: MoveKind,
        pos: i32,
        accel: i32,
        vel: i32,
        cond: Option<Cond>,
    ) -> Exec {
        let (accel, vel) = (accel as u32, vel as u32);
        if !(1..=1 << 30).contains(&accel) {
            return Err(Raise(
                FaultKind::BadMotion,
                format!("acceleration {accel} is outside 1 ..= 1073741824 (native units)"),
            ));
        }
        if vel > 1 << 31 {
            return Err(Raise(
                FaultKind::BadMotion,
                format!("velocity {vel} is outside 0 ..= 2147483648 (native units)"),
            ));
        }
        let start = self.s.regs[0];
        let operand = if kind.takes_register() {
            self.s.regs[pos as usize]
        } else {
            pos
        };
        let end = if kind.is_relative() {
            let end = i64::from(start) + i64::from(operand);
            i32::try_from(end).map_err(|_| {
                Raise(
                    FaultKind::BadMotion,
                    format!("target {start} + {operand} = {end} does not fit in 32 bits"),
                )
            })?
        } else {
            operand
        };
        self.record([start, end, operand, 0], Outcome::Done);
        self.s.isw &= !isw::INPUT_FOUND;
        self.s.psw &= !psw::INPUT_FOUND;
        let m = &mut self.s.motion;
        if m.settled {
            // Wake the follower exactly where the registers say the motor is.
            m.x = i64::from(self.s.regs[1]) << FRAC;
            m.v = 0;
        }
        m.start(start, end, accel, vel, cond);
        m.settled = false;
        self.s.run = RunState::Waiting(WaitReason::Move);
        Ok(())
    }

    /// SUB_TARGET / ZTP: move the zero point; the motor does not move.
    pub(super) fn shift_positions(&mut self, target_by: i64, actual_by: i64) {
        let regs = &mut self.s.regs;
        regs[0] = regs[0].wrapping_sub(target_by as i32);
        regs[1] = regs[1].wrapping_sub(actual_by as i32);
        regs[6] = regs[0].wrapping_sub(regs[1]);
        let m = &mut self.s.motion;
        m.shift(target_by, actual_by);
        m.seen_r0 = regs[0];
        m.seen_r1 = regs[1];
    }

    /// The motion phase of a tick. Costs a few compares while the motor is at rest.
    #[inline(always)]
    pub(super) fn motion_tick(&mut self) {
        let m = &self.s.motion;
        // `settled` implies no trajectory; R0 and R1 unchanged since the model last wrote them.
        let idle = m.settled && (m.seen_r0, m.seen_r1) == (self.s.regs[0], self.s.regs[1]);
        if idle {
            self.s.motion_ticked = false;
        } else {
            self.s.motion_ticked = true;
            self.motion_step();
        }
    }

    fn motion_step(&mut self) {
        let regs = &mut self.s.regs;
        let m = &mut self.s.motion;
        if regs[1] != m.seen_r1 {
            // A program or the user wrote the actual position: the motor is now there.
            m.x = i64::from(regs[1]) << FRAC;
            m.v = 0;
        }
        if m.active && !m.stopping && m.stop_cond.is_some_and(|c| c.holds(self.s.isw)) {
            m.stopping = true;
            regs[4] = regs[1];
            self.s.isw |= isw::INPUT_FOUND;
            self.s.psw |= psw::INPUT_FOUND;
        }
        let moving = m.active;
        let reference = if m.active {
            regs[0] = m.advance_trajectory();
            m.pos
        } else {
            i64::from(regs[0]) << FRAC
        };
        m.settled = false;
        regs[1] = m.advance_follower(reference, self.k1, self.k2);
        regs[6] = regs[0].wrapping_sub(regs[1]);
        regs[7] = m.v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32;
        m.seen_r0 = regs[0];
        m.seen_r1 = regs[1];
        let err = regs[6].unsigned_abs();
        let mut bits = self.s.isw & !(isw::MOVING_ERROR | isw::HOLDING_ERROR);
        if moving && err > self.settings.moving_error_limit {
            bits |= isw::MOVING_ERROR;
        }
        if !moving && err > self.settings.holding_error_limit {
            bits |= isw::HOLDING_ERROR;
        }
        self.s.isw = bits;
    }

    /// Whether the motion model has nothing to do this tick (see `motion_tick`).
    #[inline(always)]
    pub(in crate::machine::silverlode) fn motion_idle(&self) -> bool {
        let m = &self.s.motion;
        m.settled && (m.seen_r0, m.seen_r1) == (self.s.regs[0], self.s.regs[1])
    }
}
