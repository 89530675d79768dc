//! What a user asks of the debugger, as data: a window's panel, a key, a test or a script
//! emits an [`Action`] and [`Debugger::apply`] carries it out. The window's own commands
//! (dialogs, files, layout, lessons) are the app's; these are the debugger's alone.

use super::{Breakpoint, ChannelChoice, Debugger, EditError, Speed, Watch};
use crate::machine::{Loc, Pos};

#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// One instruction, into a call (F11).
    StepCommand,
    /// One instruction, over a call (F10).
    StepOver,
    /// Until the subroutine on hand returns (Shift+F11).
    StepOut,
    StepTick,
    /// One instruction back, into a call that just returned (Ctrl+Shift+F10).
    StepBackCommand,
    /// One instruction back, over a call that just returned (Shift+F10).
    StepBackOver,
    /// Back to the CALL that entered the subroutine on hand (Ctrl+Shift+F11).
    StepBackOut,
    StepBackTick,
    ReverseContinue,
    GoToTick(u64),
    /// Go to a position of the recorded run (a log entry).
    GoTo(Pos),
    Run,
    Pause,
    Reset,
    RunToLine(usize),
    ToggleBreakpoint(usize),
    UpdateBreakpoint(usize, Breakpoint),
    RemoveBreakpoint(usize),
    /// Stop a run when the machine's error lamp turns on.
    SetBreakOnError(bool),
    Assemble,
    SetSpeed(Speed),
    SetInput(Loc, bool),
    SetValue(Loc, u64),
    ToggleBit(Loc, u8),
    SetBit(Loc, u8, bool),
    /// Force a bit ON/OFF (Some) or release it (None).
    Force(Loc, Option<bool>),
    ReleaseAllForces,
    SetChannels(Vec<ChannelChoice>),
    UpdateWatch(usize, Watch),
    RemoveWatch(usize),
}

impl Debugger {
    /// Carry out `action`. An edit the machine refuses changes nothing and says why.
    pub fn apply(&mut self, action: Action) -> Result<(), EditError> {
        match action {
            Action::StepCommand => self.step_command(),
            Action::StepOver => self.step_over(),
            Action::StepOut => self.step_out(),
            Action::StepTick => self.step_tick(),
            Action::StepBackCommand => self.step_back_command(),
            Action::StepBackOver => self.step_back_over(),
            Action::StepBackOut => self.step_back_out(),
            Action::StepBackTick => self.step_back_tick(),
            Action::ReverseContinue => self.reverse_continue(),
            Action::GoToTick(tick) => self.goto_tick(tick),
            Action::GoTo(pos) => self.goto(pos),
            Action::Run => self.run(),
            Action::Pause => self.pause(),
            Action::Reset => self.reset(),
            Action::RunToLine(line) => self.run_to_line(line),
            Action::ToggleBreakpoint(line) => {
                self.toggle_breakpoint(line);
            }
            Action::UpdateBreakpoint(i, b) => self.update_breakpoint(i, b),
            Action::RemoveBreakpoint(i) => self.remove_breakpoint(i),
            Action::SetBreakOnError(on) => self.set_break_on_error(on),
            Action::Assemble => {
                self.assemble();
            }
            Action::SetSpeed(speed) => self.set_speed(speed),
            Action::SetInput(loc, high) => return self.set_input(loc, high),
            Action::SetValue(loc, value) => return self.set_value(loc, value),
            Action::ToggleBit(loc, bit) => return self.toggle_bit(loc, bit),
            Action::SetBit(loc, bit, on) => return self.set_bit(loc, bit, on),
            Action::Force(loc, level) => return self.force(loc, level),
            Action::ReleaseAllForces => return self.release_all_forces(),
            Action::SetChannels(channels) => self.set_channels(channels),
            Action::UpdateWatch(i, w) => self.update_watch(i, w),
            Action::RemoveWatch(i) => self.remove_watch(i),
        }
        Ok(())
    }
}
