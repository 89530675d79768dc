//! Faults (spec §5.6: state untouched by the faulting command), flow control, timing (§3) and
//! status flags (§4).

use crate::common;
use common::{flags, machine, reg, run, run_ok};
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::{Machine, MachineView, RunState, StopReason};

/// Run up to the command on `line`, then execute it; return (state before, machine after).
fn fault_at(source: &str, line: usize) -> (SilverLode, SilverLode) {
    let mut m = machine(source);
    m.run_until(1_000_000, |m| m.pc_line() == Some(line));
    let before = m.clone();
    m.run_until(1_000_000, |_| false);
    (before, m)
}

fn assert_fault(source: &str, line: usize, kind: &str) -> SilverLode {
    let (before, after) = fault_at(source, line);
    assert_eq!(after.run_state(), RunState::Faulted, "{source}");
    let fault = after.fault().expect("fault info");
    assert_eq!(fault.kind, kind, "{}", fault.message);
    assert_eq!(fault.line, line);
    assert!(!fault.message.is_empty());
    // Nothing but the command-error bit changed.
    assert_eq!(after.regs(), before.regs(), "registers untouched");
    assert_eq!(after.isw(), before.isw(), "ISW untouched");
    assert_eq!(after.psw(), before.psw() | 1 << 12, "PSW bit 12 set");
    assert_eq!(
        after.ticks(),
        before.ticks(),
        "the faulting tick is not spent"
    );
    assert_eq!(
        after.steps(),
        before.steps(),
        "the faulting command is not counted"
    );
    assert_eq!(after.pc_line(), Some(line), "pc stays on the faulting line");
    assert_eq!(after.state().motion, before.state().motion);
    after
}

#[test]
fn divide_by_zero_uses_the_low_word() {
    // 0x10000 has a zero low word: the divisor is 0 although the register is not.
    assert_fault(
        "WRP 10, 100\nWRP 11, 0x10000\nCLC DIV, 11",
        3,
        "divide_by_zero",
    );
    assert_fault("WRP 10, 100\nWRP 11, 0\nCLC MOD, 11", 3, "divide_by_zero");
    assert_fault("WRP 26, 5\nCLD DIV, 25, 26, 0", 2, "divide_by_zero");
    assert_fault("WRP 26, 0\nCLD DIV_REV, 25, 26, 7", 2, "divide_by_zero");
    assert_fault("WRP 26, 0\nCLD MOD_REV, 25, 26, 7", 2, "divide_by_zero");
    assert_fault("WRP 26, 1\nCLD DIV_U64, 25, 26, 0", 2, "divide_by_zero");
}

#[test]
fn divide_overflow() {
    // 0xFFFF is -1 as a signed 16-bit divisor.
    assert_fault(
        "WRP 26, -2147483648\nCLD DIV, 25, 26, 0xFFFF",
        2,
        "divide_overflow",
    );
    assert_fault(
        "WRP 26, -2147483648\nCLD MOD, 25, 26, -1",
        2,
        "divide_overflow",
    );
    assert_fault(
        "WRP 10, -2147483648\nWRP 11, -1\nCLC DIV, 11",
        3,
        "divide_overflow",
    );
    assert_fault(
        "WRP 26, -1\nCLD DIV_REV, 25, 26, -2147483648",
        2,
        "divide_overflow",
    );
    // 2^32 / 1 does not fit 32 bits.
    assert_fault(
        "WRP 26, 1\nWRP 27, 0\nCLD DIV_U64, 25, 26, 1",
        3,
        "divide_overflow",
    );
}

#[test]
fn queue_full_and_empty_in_the_err_variants() {
    let full =
        "CLD Q_INIT, 10, 27, 1\nCLD Q_PUSH_HEAD_ERR, 10, 27, 5\nCLD Q_PUSH_HEAD_ERR, 10, 27, 6";
    assert_fault(full, 3, "queue_full");
    let full_tail =
        "CLD Q_INIT, 10, 27, 1\nCLD Q_PUSH_TAIL_ERR, 10, 27, 5\nCLD Q_PUSH_TAIL_ERR, 10, 27, 6";
    assert_fault(full_tail, 3, "queue_full");
    assert_fault(
        "CLD Q_INIT, 10, 27, 2\nCLD Q_POP_HEAD_ERR, 33, 27, 0",
        2,
        "queue_empty",
    );
    assert_fault(
        "CLD Q_INIT, 10, 27, 2\nCLD Q_POP_TAIL_ERR, 33, 27, 0",
        2,
        "queue_empty",
    );
}

#[test]
fn flag_variants_fail_without_faulting() {
    let m = run_ok(
        "CLD Q_INIT, 10, 27, 1\nCLD Q_PUSH_HEAD, 10, 27, 5\nWRP 12, 77\nCLD Q_PUSH_HEAD, 12, 27, 6",
    );
    assert_eq!(
        flags(&m),
        (false, false, true),
        "failure sets NEGATIVE only"
    );
    assert_eq!(reg(&m, 12), 77, "result register unchanged (spec §7)");
    assert_eq!(reg(&m, 29), 5);
    let m = run_ok("CLD Q_INIT, 10, 27, 1\nWRP 12, 77\nCLD Q_POP_TAIL, 12, 27, 0");
    assert_eq!((flags(&m), reg(&m, 12)), ((false, false, true), 77));
    let m = run_ok("CLD Q_INIT, 10, 27, 1\nCLD Q_READ, 12, 27, 0");
    assert_eq!(
        flags(&m),
        (false, false, true),
        "reading an empty queue fails"
    );
}

#[test]
fn bad_queue() {
    assert_fault("CLD Q_INIT, 10, 27, 0", 1, "bad_queue");
    assert_fault("CLD Q_INIT, 10, 190, 9", 1, "bad_queue");
    assert_fault("CLD Q_INIT, 10, 199, 1", 1, "bad_queue");
    // base + 1 + size = 199 is the largest that fits.
    let m = run_ok("CLD Q_INIT, 10, 190, 8");
    assert_eq!(reg(&m, 10), 8);
    // A header that was never initialised, or was overwritten.
    assert_fault("CLD Q_PUSH_HEAD, 10, 50, 1", 1, "bad_queue");
    assert_fault(
        "CLD Q_INIT, 10, 27, 3\nWRP 28, 0x00050000\nCLD Q_POP_TAIL, 10, 27, 0",
        3,
        "bad_queue",
    );
    assert_fault(
        "CLD Q_INIT, 10, 27, 3\nWRP 27, 0x00030004\nCLD Q_READ, 10, 27, 0",
        3,
        "bad_queue",
    );
}

#[test]
fn bad_register() {
    assert_fault("WRP 11, 200\nCLC COPY_REF, 11", 2, "bad_register");
    assert_fault("WRP 11, -1\nCLC SAVE_REF, 11", 2, "bad_register");
    assert_fault("WRP 26, 2\nCLD MULT_U64, 199, 26, 3", 2, "bad_register");
    assert_fault("CLD DIV_U64, 25, 199, 3", 1, "bad_register");
}

#[test]
fn bad_motion() {
    assert_fault("MAV 100, 0, 1000", 1, "bad_motion");
    assert_fault("MAV 100, 1073741825, 1000", 1, "bad_motion");
    assert_fault("MAV 100, 10, 2147483649", 1, "bad_motion");
    assert_fault("MAV 100, 10, -1", 1, "bad_motion");
    assert_fault(
        "WRP 0, 2147483000\nWRP 1, 2147483000\nMRV 1000, 10, 1000",
        3,
        "bad_motion",
    );
}

#[test]
fn stack_overflow_and_underflow() {
    let mut deep = String::from("CALL f1\nEND\n");
    for i in 1..=9 {
        deep.push_str(&format!("f{i}: CALL f{}\n", i + 1));
    }
    deep.push_str("f10: RET\n");
    // Line 1 calls at depth 1; f8 (line 10) makes the ninth call.
    let m = assert_fault(&deep, 10, "stack_overflow");
    assert_eq!(m.call_stack_lines().len(), 8);
    assert_fault("RET", 1, "stack_underflow");
}

#[test]
fn cer_jumps_to_the_handler_and_keeps_running() {
    let m = run_ok(
        "CER handler\nWRP 11, 0\nWRP 10, 5\nCLC DIV, 11\nWRP 20, 1\nEND\nhandler: WRP 21, 1\nCER 0\nEND",
    );
    assert_eq!(reg(&m, 20), 0, "the line after the fault did not run");
    assert_eq!(reg(&m, 21), 1, "the handler ran");
    assert_eq!(reg(&m, 10), 5, "the faulting DIV wrote nothing");
    assert!(m.psw() & 1 << 12 != 0, "PSW bit 12 is still set");
    // CER, WRP, WRP, (DIV faults), handler WRP, CER 0, END: 6 steps, 7 ticks.
    assert_eq!(m.steps(), 6);
    assert_eq!(m.ticks(), 7);
    // After CER 0 a fault stops the program again.
    let m = run("CER h\nCER 0\nRET\nh: END");
    assert_eq!(m.run_state(), RunState::Faulted);
}

#[test]
fn every_command_takes_one_tick_end_included() {
    let m = run_ok("WRP 11, 1\nWRP 12, 2\nWRP 13, 3\nEND");
    assert_eq!((m.ticks(), m.steps()), (4, 4));
    assert_eq!(m.psw() & 1 << 13, 1 << 13, "program done");
}

#[test]
fn running_past_the_last_line_takes_no_tick() {
    let m = run_ok("WRP 11, 1\nWRP 12, 2\n; trailing comment\n");
    assert_eq!((m.ticks(), m.steps()), (2, 2));
    let empty = run_ok("; nothing here\n\n");
    assert_eq!((empty.ticks(), empty.steps()), (0, 0));
    // A jump to a label after the last command ends too.
    let m = run_ok("JMP out\nWRP 11, 1\nout:");
    assert_eq!((m.ticks(), m.steps(), reg(&m, 11)), (1, 1, 0));
}

#[test]
fn delays_take_their_ticks() {
    let m = run_ok("DLY 100\nEND");
    assert_eq!((m.ticks(), m.steps()), (101, 2));
    assert!(m.isw() & 1 << 12 != 0, "DELAY_DONE set");
    let m = run_ok("DLY 0\nEND");
    assert_eq!(m.ticks(), 2, "DLY 0 still takes one tick");
    // DELAY_DONE is clear while the delay runs.
    let mut m = machine("DLY 1\nDLY 5\nEND");
    m.step_tick();
    assert!(m.isw() & 1 << 12 != 0);
    m.step_tick();
    assert_eq!(m.isw() & 1 << 12, 0);
    assert_eq!(m.run_state().label(), "waiting for delay");
}

#[test]
fn jumps_test_conditions_and_their_negation() {
    // Count down from 5: the loop runs while the DEC result is not zero.
    let m = run_ok("WRP 11, 5\nloop: CLC INC, 12\nCLC DEC, 11\nJMP loop, !ZERO\nEND");
    assert_eq!(reg(&m, 12), 5);
    let m = run_ok("WRP 26, -3\nCLD COPY, 25, 26, 0\nJMP neg, NEGATIVE\nWRP 30, 1\nneg: WRP 31, 1");
    assert_eq!((reg(&m, 30), reg(&m, 31)), (0, 1));
}

#[test]
fn flags_follow_the_written_value_and_wrp_leaves_them() {
    let m = run_ok("WRP 26, 5\nCLD SUB, 25, 26, 5");
    assert_eq!(flags(&m), (true, false, false));
    let m = run_ok("WRP 26, 5\nCLD SUB, 25, 26, 6\nWRP 25, 100\nJMP x\nx: END");
    assert_eq!(
        flags(&m),
        (false, false, true),
        "WRP and JMP keep the flags"
    );
    let m = run_ok("WRP 26, -1\nCLD MULT_U64, 30, 26, 2");
    assert_eq!(
        flags(&m),
        (false, true, false),
        "MULT_U64 flags from the unsigned 64-bit result"
    );
}

#[test]
fn call_and_return() {
    let m = run_ok("CALL twice\nCALL twice\nEND\ntwice: CLC INC, 11\nCLC INC, 11\nRET");
    assert_eq!(reg(&m, 11), 4);
    let mut m = machine("CALL f\nEND\nf: CALL g\nRET\ng: RET");
    m.step_command(1);
    m.step_command(1);
    assert_eq!(
        m.call_stack_lines(),
        vec![2, 4],
        "return lines, outermost first"
    );
}

#[test]
fn wbs_waits_for_an_input() {
    let mut m = machine("WBS IO2\nWRP 11, 1\nEND");
    assert_eq!(m.run_until(50, |_| false), StopReason::TickLimit);
    assert_eq!(m.run_state().label(), "waiting for input");
    m.set_io(1, true);
    assert!(m.isw() & 1 << 5 != 0, "ISW bit 5 mirrors IO2");
    m.run_until(1000, |_| false);
    assert_eq!(m.run_state(), RunState::Ended);
    assert_eq!(
        m.ticks(),
        53,
        "50 waiting ticks, the tick the condition held, WRP, END"
    );
}

#[test]
fn step_command_and_breakpoint_predicates() {
    let mut m = machine("WRP 11, 1\nDLY 10\nWRP 12, 2\nEND");
    m.step_command(1_000);
    assert_eq!((m.pc_line(), m.ticks()), (Some(2), 1));
    m.step_command(1_000);
    assert_eq!(
        (m.pc_line(), m.ticks()),
        (Some(3), 11),
        "a step waits out the whole delay"
    );
    let mut m = machine("WRP 11, 1\nDLY 10\nWRP 12, 2\nEND");
    assert_eq!(
        m.run_until(1_000, |m| m.pc_line() == Some(3)),
        StopReason::Predicate
    );
    assert_eq!(reg(&m, 12), 0, "stopped before the breakpoint line runs");
}

#[test]
fn the_machine_is_deterministic() {
    let src = "CLD Q_INIT, 10, 40, 5\nloop: CLD Q_PUSH_HEAD, 11, 40, 7\nCLD Q_POP_TAIL, 12, 40, 0\nMRV 500, 3865, 8053064\nCLC INC, 20\nCLD SUB, 21, 20, 4\nJMP loop, !ZERO\nEND";
    let a = run(src);
    let b = run(src);
    assert_eq!(a, b);
    assert_eq!(a.run_state(), RunState::Ended);
}

#[test]
fn explanations_show_operands_and_values() {
    let mut m = machine(
        "WRP 26, 1000\nCLD MULT_S64_SHR16, 25, 26, 16668865\nCLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD, 10, 27, 10\nCLD Q_PUSH_HEAD, 10, 27, 20\nCLD Q_PUSH_HEAD, 10, 27, 30",
    );
    m.step_command(1);
    m.step_command(1);
    assert_eq!(
        m.explain_last().as_deref(),
        // The vendor's worked example: 254346.7 truncates to 254346; 0.694946 (of 2^-16
        // steps: 45543 / 65536) is what the shift dropped.
        Some(
            "R25 = (R26 × 16668865) >> 16 = (1000 × 16668865) >> 16 = 254346 — 0.694946 dropped by the shift"
        )
    );
    assert_eq!(m.written_by_last(), vec![25]);
    for _ in 0..4 {
        m.step_command(1);
    }
    assert_eq!(
        m.explain_last().as_deref(),
        Some("push 30 at head of queue R27: slot 2 (R31), head 2→0, len 2→3; R10 = 0 free")
    );
    assert_eq!(m.written_by_last(), vec![10, 27, 28, 31]);
}

/// Issue #22 item 17: step over runs a CALL's subroutine whole, step out runs to its return,
/// and both have backward versions; a breakpoint inside the subroutine still stops a step over.
mod step_over_and_out {
    use std::time::Duration;

    use servoscope_core::debugger::{Breakpoint, Debugger, Speed};

    const CALLS: &str = include_str!("../../../../assets/examples/call_ret.qsl");

    fn settle(d: &mut Debugger) {
        while d.advance(0.016, Duration::from_millis(200)) {}
    }

    fn line(d: &Debugger) -> Option<usize> {
        d.machine().pc_line()
    }

    fn r(d: &Debugger, name: &str) -> u64 {
        d.machine().read(d.find(name).expect("a location"))
    }

    #[test]
    fn over_into_and_out_of_a_call() {
        let mut d = Debugger::new("call_ret.qsl", CALLS);
        d.set_speed(Speed::PerSecond(1.0)); // stepping ignores the run speed
        d.step_over(); // WRP n, 10
        assert_eq!(line(&d), Some(11));
        // Over the CALL: the square is computed, the next line is the CLX ADD.
        d.step_over();
        settle(&mut d);
        assert_eq!(line(&d), Some(12), "stopped after the subroutine");
        assert_eq!(r(&d, "square"), 100);
        assert_eq!(d.machine().call_depth(), 0);
        // Into the next CALL (F11): inside the subroutine, one deep.
        d.step_over(); // CLX ADD
        d.step_over(); // CLC DEC
        d.step_over(); // JMP loop
        assert_eq!(line(&d), Some(11));
        d.step_command();
        assert_eq!(line(&d), Some(18), "into square_n");
        assert_eq!(d.machine().call_depth(), 1);
        // Out: runs to the return, back in the caller after the CALL.
        d.step_out();
        settle(&mut d);
        assert_eq!(line(&d), Some(12));
        assert_eq!(d.machine().call_depth(), 0);
        assert_eq!(r(&d, "square"), 81);

        // Backward: over the call that just returned, back to the CALL itself.
        d.step_back_over();
        settle(&mut d);
        assert_eq!(line(&d), Some(11), "back before the CALL");
        assert_eq!(d.machine().call_depth(), 0);
        assert_eq!(r(&d, "square"), 100, "the square of the previous round");
        // Into it again and back out of it: to the CALL.
        d.step_command();
        d.step_command();
        assert_eq!(line(&d), Some(19), "at the RET");
        d.step_back_out();
        settle(&mut d);
        assert_eq!(line(&d), Some(11));
        assert_eq!(d.machine().call_depth(), 0);
    }

    #[test]
    fn a_breakpoint_inside_the_subroutine_stops_a_step_over() {
        let mut d = Debugger::new("call_ret.qsl", CALLS);
        d.step_over();
        d.add_breakpoint(Breakpoint::line(19));
        d.step_over();
        settle(&mut d);
        assert_eq!(line(&d), Some(19), "at the breakpoint on RET");
        assert_eq!(d.machine().call_depth(), 1);
    }

    #[test]
    fn step_out_at_the_outermost_level_runs_on() {
        let mut d = Debugger::new("call_ret.qsl", CALLS);
        d.set_speed(Speed::Unlimited);
        d.step_out();
        settle(&mut d);
        assert_eq!(r(&d, "total"), 385, "ran to the end");
    }
}
