//! The last instruction in words, with its values (spec issue: "SUBS: ACC 00395026 − L1
//! 00172056 = 00222970 (BCD); pop: L1 ← L2 … L8 ← 0").

use super::program::{Math, Op, Src, Test, bit_name};
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
    let power = m.power.get(m.last? as usize).copied().flatten().unwrap_or(false);
    Some(match ins.op {
        Op::Str(t) | Op::And(t) | Op::Or(t) => {
            let what = match t {
                Test::Bit(b, neg) => format!("{}{} = {}", if neg { "NOT " } else { "" }, bit_name(b), u8::from(m.bit(b) != neg)),
                Test::Compare(..) => "compare".into(),
            };
            format!("{text}: {what}; rung power {}", u8::from(power))
        }
        Op::AndStr | Op::OrStr => format!("{text}: rung power {}", u8::from(power)),
        Op::Coil(b) => format!("{text}: {} = {}", bit_name(b), u8::from(m.bit(b))),
        Op::End => format!("END: scan {} done", m.tick.saturating_sub(1)),
        Op::Nop => "NOP".into(),
        _ if !m.last_ran => format!("{text}: rung not powered, skipped"),
        Op::Ld(_) | Op::Ldd(_) | Op::Lda(_) | Op::Ldf(..) => match m.moved {
            StackMove::Push { .. } => format!("{text}: load pending → push ACC {a:08X} to L1; ACC = {:08X}", m.acc),
            _ => format!("{text}: ACC = {:08X}", m.acc),
        },
        Op::OutV(_) | Op::OutD(_) | Op::OutF(..) => format!("{text}: ACC {:08X} out; the next load will not push", m.acc),
        Op::Pop => format!("POP: ACC = L1 {:08X}; L1 ← L2 … L8 ← 0", m.acc),
        Op::Bcd(op, src) | Op::Binary(op, src) => {
            let bcd = matches!(ins.op, Op::Bcd(..));
            if bcd && m.sp[super::program::sp::SP75] && m.acc == a && m.moved == StackMove::None && m.sp75_line == Some(ins.line) {
                return Some(format!("{text}: a non-BCD digit: SP75 = 1, nothing else changed"));
            }
            if m.sp[super::program::sp::SP53] && m.sp53_line == Some(ins.line) && m.acc == a && m.moved == StackMove::None {
                return Some(format!("{text}: divide by zero: SP53 = 1, nothing else changed"));
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
            let by = if matches!(ins.op, Op::IncB(_)) { "+ 1" } else { "− 1" };
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
        Op::ToBin if m.flags_written(ins.op, ins.line) == [super::program::sp::SP75] => {
            format!("{text}: ACC {a:08X} has a non-BCD digit: SP75 = 1, ACC unchanged")
        }
        _ => format!("{text}: ACC = {:08X}{}", m.acc, stack_note(m)),
    })
}
