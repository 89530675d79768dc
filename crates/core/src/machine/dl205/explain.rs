//! The last instruction in words, with its values (spec issue: "SUBS: ACC 00395026 − L1
//! 00172056 = 00222970 (BCD); pop: L1 ← L2 … L8 ← 0").

use super::program::{
    CounterKind, Kind, Math, Op, Preset, Src, Test, TimerKind, bit_name, current_word, sp,
};
use super::{Dl205, StackMove};

fn stack_note(m: &Dl205) -> String {
    match m.moved {
        StackMove::None => String::new(),
        StackMove::Push {
            entered,
            lost: Some(lost),
        } => format!("; push {entered:08X} to L1 (L8 {lost:08X} falls off)"),
        StackMove::Push { entered, .. } => format!("; push {entered:08X} to L1"),
        StackMove::Pop { .. } => "; pop: L1 ← L2 … L8 ← 0".into(),
        StackMove::Overwrite { value } => format!("; L1 = remainder {value:08X}"),
    }
}

/// The carry, borrow and overflow relays the instruction turned on, by name and meaning:
/// " — SP66 = 1: carry out of the low word".
fn carry_note(m: &Dl205, op: super::program::Op, line: usize) -> String {
    use super::program::sp::{SP64, SP65, SP66, SP67, SP73};
    m.flags_written(op, line)
        .iter()
        .filter(|&&f| matches!(f, SP64 | SP65 | SP66 | SP67 | SP73) && m.sp[f])
        .map(|&f| {
            format!(
                " — SP{:o} = 1: {}",
                super::program::SPECIAL[f],
                super::view::SP_DESCRIPTIONS[f]
            )
        })
        .collect()
}

pub fn explain(m: &Dl205) -> Option<String> {
    let ins = m.program.instrs.get(m.last? as usize)?;
    let name = ins.mnemonic.as_str();
    let text = ins.text.as_str();
    let (a, l1) = m.before;
    let power = m
        .power
        .get(m.last? as usize)
        .copied()
        .flatten()
        .unwrap_or(false);
    Some(match ins.op {
        Op::Str(t) | Op::And(t) | Op::Or(t) => {
            let what = match t {
                Test::Bit(b, neg) => format!(
                    "{}{} = {}",
                    if neg { "NOT " } else { "" },
                    bit_name(b),
                    u8::from(m.bit(b) != neg)
                ),
                Test::Compare(..) => "compare".into(),
                Test::Edge(b, edge, _) => {
                    let change = match edge {
                        super::program::Edge::Rising => "turned on",
                        super::program::Edge::Falling => "turned off",
                    };
                    let fired = m.edge_fired;
                    format!(
                        "{} is {}; {}",
                        bit_name(b),
                        u8::from(m.bit(b)),
                        if fired {
                            format!("it {change} since the last execution: fires")
                        } else {
                            format!("it has not {change} since the last execution")
                        }
                    )
                }
            };
            format!("{text}: {what}; rung power {}", u8::from(power))
        }
        Op::AndStr | Op::OrStr | Op::Not => format!("{text}: rung power {}", u8::from(power)),
        Op::Pd(b, _) => format!(
            "{text}: {} = {} (on for one scan after the rung turns on)",
            bit_name(b),
            u8::from(m.bit(b))
        ),
        Op::OrOut(b, _) => format!(
            "{text}: {} = {} (ORed with the earlier OROUTs of this scan)",
            bit_name(b),
            u8::from(m.bit(b))
        ),
        Op::Timer(kind, n, preset) => timer_text(m, text, kind, n, preset),
        Op::Counter(kind, n, preset) => counter_text(m, text, kind, n, preset),
        Op::Coil(b) => format!("{text}: {} = {}", bit_name(b), u8::from(m.bit(b))),
        Op::End => format!("END: scan {} done", m.tick.saturating_sub(1)),
        Op::Lbl(_) => format!("{text}: a jump target"),
        Op::Next(for_at) => match m.loop_state {
            Some(l) => format!(
                "{text}: back to the top of the loop ({} turn(s) left)",
                l.left
            ),
            None => format!("{text}: loop done (FOR on line {})", line_of(m, for_at)),
        },
        Op::Sbr(_) => format!("{text}: subroutine starts (call depth {})", m.calls.len()),
        Op::Rt => format!("{text}: return to line {}", m.pc_line_now()),
        Op::Mlr(n) => format!("{text}: master-line level {n}"),
        Op::Mls(n) => format!(
            "{text}: zone {n} {} (level {n})",
            if m.zones[usize::from(n.min(7))] {
                "powered"
            } else {
                "not powered: its outputs see no power"
            }
        ),
        Op::Sg { stage, next, .. } => {
            if m.pc == next && !m.s[stage as usize] {
                format!(
                    "{text}: S{stage:o} is off: skipped to line {}",
                    line_of(m, next)
                )
            } else if m.stage_power {
                format!("{text}: S{stage:o} is on: the stage runs")
            } else {
                format!(
                    "{text}: S{stage:o} turned off: one clean-up pass (outputs off, timers reset)"
                )
            }
        }
        Op::Njmp { to, own } => {
            if m.s[to as usize] && !m.s[own as usize] && !power {
                format!("{text}: rung off: stage S{own:o} → S{to:o}")
            } else {
                format!("{text}: rung on: stays in S{own:o}")
            }
        }
        Op::Nop => "NOP".into(),
        _ if !m.last_ran => format!("{text}: rung not powered, skipped"),
        Op::Ld(_) | Op::Ldd(_) | Op::Lda(_) | Op::Ldf(..) => match m.moved {
            StackMove::Push { .. } => format!(
                "{text}: load pending → push ACC {a:08X} to L1; ACC = {:08X}",
                m.acc
            ),
            _ => format!("{text}: ACC = {:08X}", m.acc),
        },
        Op::OutV(_) | Op::OutD(_) | Op::OutF(..) => {
            format!("{text}: ACC {:08X} out; the next load will not push", m.acc)
        }
        Op::Pop => format!("POP: ACC = L1 {:08X}; L1 ← L2 … L8 ← 0", m.acc),
        Op::Bcd(op, src) | Op::Binary(op, src) => {
            let bcd = matches!(ins.op, Op::Bcd(..));
            if bcd
                && m.sp[super::program::sp::SP75]
                && m.acc == a
                && m.moved == StackMove::None
                && m.sp75_line == Some(ins.line)
            {
                return Some(format!(
                    "{text}: a non-BCD digit: SP75 = 1, nothing else changed"
                ));
            }
            if m.sp[super::program::sp::SP53]
                && m.sp53_line == Some(ins.line)
                && m.acc == a
                && m.moved == StackMove::None
            {
                return Some(format!(
                    "{text}: divide by zero: SP53 = 1, nothing else changed"
                ));
            }
            let sign = match op {
                Math::Add => "+",
                Math::Sub => "−",
                Math::Mul => "×",
                Math::Div => "÷",
            };
            let operand = match src {
                Src::Stack => format!("L1 {l1:08X}"),
                _ => text.split_whitespace().nth(1).unwrap_or("").to_string(),
            };
            format!(
                "{name}: ACC {a:08X} {sign} {operand} = {:08X}{}{}{}",
                m.acc,
                if bcd { " (BCD)" } else { "" },
                stack_note(m),
                carry_note(m, ins.op, ins.line)
            )
        }
        // These leave ACC and the stack alone: say what they wrote.
        Op::IncB(a) | Op::DecB(a) => {
            let now = m.v.get(a as usize).copied().unwrap_or(0);
            let by = if matches!(ins.op, Op::IncB(_)) {
                "+ 1"
            } else {
                "− 1"
            };
            let was = if matches!(ins.op, Op::IncB(_)) {
                now.wrapping_sub(1)
            } else {
                now.wrapping_add(1)
            };
            format!("{text}: V{a:o} = {was:04X} {by} = {now:04X} (binary; ACC untouched)")
        }
        Op::Set(from, to) | Op::Rst(from, to) => {
            let on = matches!(ins.op, Op::Set(..));
            let range = if from == to {
                bit_name(from)
            } else {
                format!("{} … {}", bit_name(from), bit_name(to))
            };
            format!("{text}: {range} = {}", u8::from(on))
        }
        Op::Table(kind, operand) => match m.table_span() {
            None => format!("{text}: the count in L1 is not BCD: SP75 = 1, nothing else changed"),
            Some(_) if m.raised_error => {
                format!("{text}: the table runs past V37777: SP53 = 1, nothing else changed")
            }
            Some((start, count)) => match kind {
                super::program::Table::Mov => {
                    format!("{text}: {count} word(s) V{start:o}… copied to V{operand:o}…")
                }
                _ => format!(
                    "{text}: bit {} of V{:o} = {}",
                    operand % 16,
                    start + operand / 16,
                    u8::from(kind == super::program::Table::SetBit)
                ),
            },
        },
        Op::Goto(to) => format!("{text}: jump to line {}", line_of(m, to)),
        Op::For(_, next) => match m.loop_state {
            Some(l) if m.pc != next + 1 => format!("{text}: loop of {} turn(s)", l.left),
            _ => format!(
                "{text}: no turns: continue after NEXT (line {})",
                line_of(m, next)
            ),
        },
        Op::Gts(to) => format!(
            "{text}: call the subroutine on line {} (depth {})",
            line_of(m, to),
            m.calls.len()
        ),
        Op::Rtc => format!("{text}: return to line {}", m.pc_line_now()),
        Op::Jmp { to, own } => format!("{text}: stage S{own:o} → S{to:o}"),
        Op::Cmp(_) | Op::CmpD(_) => {
            let which = if m.sp[sp::SP60] {
                "less than: SP60 = 1"
            } else if m.sp[sp::SP61] {
                "equal: SP61 = 1"
            } else {
                "greater than: SP62 = 1"
            };
            let lo = if matches!(ins.op, Op::Cmp(_)) {
                "low word of "
            } else {
                ""
            };
            format!("{text}: {lo}ACC {a:08X} is {which} (unsigned)")
        }
        Op::ToBin if m.flags_written(ins.op, ins.line) == [super::program::sp::SP75] => {
            format!("{text}: ACC {a:08X} has a non-BCD digit: SP75 = 1, ACC unchanged")
        }
        _ => format!("{text}: ACC = {:08X}{}", m.acc, stack_note(m)),
    })
}

/// A box's value in its digits, or "not BCD".
fn digits(v: u32, words: u32) -> String {
    match super::bcd_value(v, 4 * words) {
        Some(n) => n.to_string(),
        None => format!("{v:X} (not BCD)"),
    }
}

fn preset_text(m: &Dl205, preset: Preset, words: u32) -> String {
    digits(m.preset(preset), words)
}

/// "TMR T1 K30: enabled, TA1 = 29: 2.9 s of 3.0 s; T1 = 0".
fn timer_text(m: &Dl205, text: &str, kind: TimerKind, n: u32, preset: Preset) -> String {
    let words = if kind.accumulating() { 2 } else { 1 };
    let now = m.box_value(n, words);
    let status = format!("T{n:o} = {}", u8::from(m.t[n as usize]));
    let (enable, reset) = if kind.accumulating() {
        (m.leg(0), m.leg(1))
    } else {
        let p = m
            .power
            .get(m.last.unwrap_or(0) as usize)
            .copied()
            .flatten()
            .unwrap_or(false);
        (p, !p)
    };
    if reset {
        return format!("{text}: reset: TA{n:o} = 0; {status}");
    }
    if !enable {
        return format!(
            "{text}: not enabled: TA{n:o} holds {}; {status}",
            digits(now, words)
        );
    }
    if m.raised_error && super::bcd_value(now, 4 * words).is_none() {
        return format!("{text}: TA{n:o} = {now:X} is not BCD: not counted, SP75 = 1; {status}");
    }
    let seconds = |v: u32| {
        super::bcd_value(v, 4 * words).map(|units| {
            let ms = units * u64::from(kind.unit_ms());
            format!(
                "{}.{:0w$} s",
                ms / 1000,
                (ms % 1000) / u64::from(kind.unit_ms()),
                w = if kind.unit_ms() == 10 { 2 } else { 1 }
            )
        })
    };
    let of = match (seconds(now), seconds(m.preset(preset))) {
        (Some(a), Some(b)) => format!(": {a} of {b}"),
        _ => String::new(),
    };
    format!(
        "{text}: enabled, TA{n:o} {} → {}{of}; {status}",
        digits(m.box_before, words),
        digits(now, words)
    )
}

/// "CNT CT3 K10: counted 4 → 5; CT3 = 0".
fn counter_text(m: &Dl205, text: &str, kind: CounterKind, n: u32, preset: Preset) -> String {
    let words = if kind == CounterKind::Udc { 2 } else { 1 };
    let now = m.box_value(current_word(Kind::Ct, n), words);
    let status = format!(
        "CT{n:o} = {} (preset {})",
        u8::from(m.ct[n as usize]),
        preset_text(m, preset, words)
    );
    let reset = match kind {
        CounterKind::Cnt => m.leg(1),
        CounterKind::Udc => m.leg(2),
        CounterKind::Sgcnt => false,
    };
    if reset {
        return format!("{text}: reset: CTA{n:o} = 0; {status}");
    }
    let (was, is) = (digits(m.box_before, words), digits(now, words));
    if m.box_before == now {
        if m.raised_error {
            return format!(
                "{text}: CTA{n:o} = {now:X} is not BCD: not counted, SP75 = 1; {status}"
            );
        }
        return format!(
            "{text}: no count (no off→on change of an input): CTA{n:o} stays {is}; {status}"
        );
    }
    format!("{text}: CT{n:o} counted {was} → {is}; {status}")
}

fn line_of(m: &Dl205, index: u32) -> usize {
    m.program.instrs.get(index as usize).map_or(0, |i| i.line)
}
