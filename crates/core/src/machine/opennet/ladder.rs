//! OpenNet instructions as ladder steps (spec §5): LOD/AND/OR contacts and compare contacts,
//! ANDLOD/ORLOD blocks, the BPS/BRD/BPP branch stack, SOTU/SOTD, coils (OUT, OUTN, SET, RST),
//! boxes for everything else; counters and shift registers take a leg per input in program
//! order (CNT: reset and pulse; CDP/CUD and SFR: three).

use super::OpenNet;
use super::program::{Bit, CounterKind, Instr, Op, Word, point_name};
use crate::machine::plc::ladder::{CoilKind, EdgeKind, Element, Ladder, Step, Symbol};

/// The ladder diagram of an assembled program.
/// The program's rungs, wired, not laid out (see [`Ladder::lay_out`]).
pub fn build(instrs: &[Instr]) -> Ladder {
    Ladder::wire(instrs.iter().enumerate().map(|(i, ins)| step(i, ins)))
}

pub fn bit_name(b: Bit) -> String {
    match b {
        Bit::Point(area, i) => point_name(area, i),
        Bit::Special(s) => format!("M{}", super::program::SPECIAL[s as usize]),
        Bit::Timer(n) => format!("T{n}"),
        Bit::Counter(n) => format!("C{n}"),
    }
}

fn word_name(w: Word) -> Option<String> {
    match w {
        Word::Reg { n, .. } => Some(format!("D{n}")),
        Word::Timer { n, .. } => Some(format!("T{n}.current")),
        Word::Counter { n, .. } => Some(format!("C{n}.current")),
        Word::Const(_) | Word::Bits { .. } => None,
    }
}

fn contact(i: usize, ins: &Instr, b: Bit, closed: bool) -> Element {
    Element::new(
        Symbol::Contact { closed, edge: None },
        i,
        ins.line,
        bit_name(b),
    )
}

fn coil(i: usize, ins: &Instr, kind: CoilKind, b: Bit) -> Element {
    Element::new(Symbol::Coil(kind), i, ins.line, bit_name(b))
}

fn mnemonic(ins: &Instr) -> String {
    ins.text
        .split_whitespace()
        .next()
        .unwrap_or("")
        .to_ascii_uppercase()
}

fn boxed(i: usize, ins: &Instr) -> Element {
    let values: Vec<String> = match ins.op {
        Op::Timer { n, preset, .. } | Op::Counter { n, preset, .. } => {
            let kind = if matches!(ins.op, Op::Timer { .. }) {
                'T'
            } else {
                'C'
            };
            let mut v = vec![format!("{kind}{n}.current")];
            // A preset from a data register is shown beside the current value.
            if let super::program::Value::Reg(r) = preset {
                v.push(format!("D{r}"));
            }
            v
        }
        Op::Mov { dst, .. }
        | Op::Arith { dst, .. }
        | Op::WordLogic { dst, .. }
        | Op::Convert { dst, .. } => word_name(dst).into_iter().collect(),
        Op::Shift { word, .. } => word_name(word).into_iter().collect(),
        Op::Step { reg, .. } => vec![format!("D{reg}")],
        _ => Vec::new(),
    };
    Element::new(Symbol::Box, i, ins.line, mnemonic(ins))
        .text(ins.text.split_whitespace().collect::<Vec<_>>().join(" "))
        .values(values)
}

fn step(i: usize, ins: &Instr) -> Step {
    match ins.op {
        Op::Lod(b, closed) => Step::Load(contact(i, ins, b, closed)),
        Op::And(b, closed) => Step::And(contact(i, ins, b, closed)),
        Op::Or(b, closed) => Step::Or(contact(i, ins, b, closed)),
        Op::Compare { .. } => {
            let words: Vec<&str> = ins.text.split_whitespace().collect();
            let operand = words.get(1).copied().unwrap_or("");
            let text = words.join(" ");
            Step::Load(Element::new(Symbol::Compare, i, ins.line, operand).text(text))
        }
        Op::AndLod => Step::AndBlock,
        Op::OrLod => Step::OrBlock,
        Op::Bps => Step::Push,
        Op::Brd => Step::Read,
        Op::Bpp => Step::Pop,
        Op::Sotu(_) => Step::Series(Element::new(
            Symbol::PowerEdge(EdgeKind::Rising),
            i,
            ins.line,
            "SOTU",
        )),
        Op::Sotd(_) => Step::Series(Element::new(
            Symbol::PowerEdge(EdgeKind::Falling),
            i,
            ins.line,
            "SOTD",
        )),
        Op::Out(b, neg) => Step::Output(coil(
            i,
            ins,
            if neg { CoilKind::OutNot } else { CoilKind::Out },
            b,
        )),
        Op::Set(b) => Step::Output(coil(i, ins, CoilKind::Set, b)),
        Op::Rst(b) => Step::Output(coil(i, ins, CoilKind::Reset, b)),
        Op::Nop => Step::Skip,
        Op::End | Op::Mcr | Op::Jend => Step::Alone(boxed(i, ins)),
        Op::Counter { kind, .. } => {
            let legs = if kind == CounterKind::Cnt { 2 } else { 3 };
            Step::Boxed(boxed(i, ins), legs)
        }
        Op::ShiftRegister { .. } => Step::Boxed(boxed(i, ins), 3),
        _ => Step::Output(boxed(i, ins)),
    }
}

impl OpenNet {
    /// Whether the contact of instruction `index` conducts now (SOTU/SOTD: pulsed in the scan
    /// shown).
    pub fn conducts(&self, index: usize) -> bool {
        let Some(ins) = self.program.instrs.get(index) else {
            return false;
        };
        match ins.op {
            Op::Lod(b, closed) | Op::And(b, closed) | Op::Or(b, closed) => self.bit(b) != closed,
            Op::Compare {
                counter,
                n,
                value,
                at_least,
            } => {
                let x = if counter {
                    self.counters.get(n as usize).map_or(0, |c| c.current)
                } else {
                    self.d.get(n as usize).copied().unwrap_or(0)
                };
                let v = self.value(value);
                if at_least { x >= v } else { x == v }
            }
            Op::Sotu(m) | Op::Sotd(m) => {
                // The scan shown: the one running, or between scans the one just finished.
                let shown = if self.step > 0 {
                    self.tick + 1
                } else {
                    self.tick
                };
                self.edge_scans.get(m as usize) == Some(&shown)
            }
            _ => false,
        }
    }
}
