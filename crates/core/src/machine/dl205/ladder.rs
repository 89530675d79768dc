//! DL205 instructions as ladder steps (spec §2, §5): STR/AND/OR contacts, ANDSTR/ORSTR blocks,
//! NOT, coils (OUT, SET, RST, PD, OROUT), boxes for everything else; timers and counters take a
//! leg per input (TMRA: enable and reset; CNT: count and reset; UDC: up, down and reset).

use super::Dl205;
use super::program::{Bit, Edge, Instr, Op, Test, bit_name, box_shape};
use crate::machine::plc::ladder::{CoilKind, EdgeKind, Element, Ladder, Step, Symbol};

/// The ladder diagram of an assembled program.
/// The program's rungs, wired, not laid out (see [`Ladder::lay_out`]).
pub fn build(instrs: &[Instr]) -> Ladder {
    Ladder::wire(instrs.iter().enumerate().map(|(i, ins)| step(i, ins)))
}

fn operands(ins: &Instr) -> Vec<&str> {
    ins.text.split_whitespace().skip(1).collect()
}

fn contact(i: usize, ins: &Instr, t: Test) -> Element {
    match t {
        Test::Bit(b, closed) => Element::new(
            Symbol::Contact { closed, edge: None },
            i,
            ins.line,
            bit_name(b),
        ),
        Test::Edge(b, edge, _) => Element::new(
            Symbol::Contact {
                closed: false,
                edge: Some(match edge {
                    Edge::Rising => EdgeKind::Rising,
                    Edge::Falling => EdgeKind::Falling,
                }),
            },
            i,
            ins.line,
            bit_name(b),
        ),
        Test::Compare(_, _, cmp) => {
            let ops = operands(ins);
            let rel = match cmp {
                super::program::Cmp::Eq => "=",
                super::program::Cmp::Ne => "≠",
                super::program::Cmp::Ge => "≥",
                super::program::Cmp::Lt => "<",
            };
            let a = ops.first().copied().unwrap_or("");
            let b = ops.get(1).copied().unwrap_or("");
            Element::new(Symbol::Compare, i, ins.line, a).text(format!("{a} {rel} {b}"))
        }
    }
}

fn coil(i: usize, ins: &Instr, kind: CoilKind, b: Bit, last: Option<Bit>) -> Element {
    let text = match last {
        Some(l) if l != b => format!("{}–{}", bit_name(b), bit_name(l)),
        _ => bit_name(b),
    };
    Element::new(Symbol::Coil(kind), i, ins.line, bit_name(b)).text(text)
}

/// A box: its mnemonic as the operand, its text as written, the values it shows live.
fn boxed(i: usize, ins: &Instr) -> Element {
    // A preset in a V word is shown beside the current value.
    let preset = |p: super::program::Preset| match p {
        super::program::Preset::Word(a) | super::program::Preset::Pair(a) => {
            Some(format!("V{a:o}"))
        }
        super::program::Preset::K(_) => None,
    };
    let values = match ins.op {
        Op::Timer(_, n, p) => std::iter::once(format!("TA{n:o}"))
            .chain(preset(p))
            .collect(),
        Op::Counter(_, n, p) => std::iter::once(format!("CTA{n:o}"))
            .chain(preset(p))
            .collect(),
        Op::OutV(a) | Op::OutD(a) | Op::IncB(a) | Op::DecB(a) => vec![format!("V{a:o}")],
        Op::Ld(_)
        | Op::Ldd(_)
        | Op::Lda(_)
        | Op::Ldf(..)
        | Op::Bcd(..)
        | Op::Binary(..)
        | Op::ToBin
        | Op::ToBcd
        | Op::LogicV(..)
        | Op::LogicD(..)
        | Op::LogicS(_)
        | Op::Shift(..)
        | Op::Inv
        | Op::Pop => vec!["ACC".to_string()],
        _ => Vec::new(),
    };
    Element::new(Symbol::Box, i, ins.line, ins.mnemonic.clone())
        .text(ins.text.split_whitespace().collect::<Vec<_>>().join(" "))
        .values(values)
}

fn step(i: usize, ins: &Instr) -> Step {
    match ins.op {
        Op::Str(t) => Step::Load(contact(i, ins, t)),
        Op::And(t) => Step::And(contact(i, ins, t)),
        Op::Or(t) => Step::Or(contact(i, ins, t)),
        Op::AndStr => Step::AndBlock,
        Op::OrStr => Step::OrBlock,
        Op::Not => Step::Series(Element::new(Symbol::Invert, i, ins.line, "NOT")),
        Op::Coil(b) => Step::Output(coil(i, ins, CoilKind::Out, b, None)),
        Op::Set(a, b) => Step::Output(coil(i, ins, CoilKind::Set, a, Some(b))),
        Op::Rst(a, b) => Step::Output(coil(i, ins, CoilKind::Reset, a, Some(b))),
        Op::Pd(b, _) => Step::Output(coil(i, ins, CoilKind::Pulse, b, None)),
        Op::OrOut(b, _) => Step::Output(coil(i, ins, CoilKind::OrOut, b, None)),
        Op::Jmp { .. } | Op::Njmp { .. } => {
            let stage = operands(ins).first().copied().unwrap_or("").to_string();
            Step::Output(
                Element::new(Symbol::Coil(CoilKind::Jump), i, ins.line, stage)
                    .text(ins.text.split_whitespace().collect::<Vec<_>>().join(" ")),
            )
        }
        Op::Nop => Step::Skip,
        op if op.is_standalone() => Step::Alone(boxed(i, ins)),
        op => match box_shape(&op) {
            Some((_, legs)) => Step::Boxed(boxed(i, ins), legs),
            None => Step::Output(boxed(i, ins)),
        },
    }
}

impl Dl205 {
    /// Whether the contact of instruction `index` conducts now (edge contacts: fired in this
    /// scan).
    pub fn conducts(&self, index: usize) -> bool {
        let Some(ins) = self.program.instrs.get(index) else {
            return false;
        };
        let t = match ins.op {
            Op::Str(t) | Op::And(t) | Op::Or(t) => t,
            _ => return false,
        };
        match t {
            Test::Bit(b, closed) => self.bit(b) != closed,
            Test::Edge(..) => self.fired_this_scan.contains(&(index as u32)),
            Test::Compare(a, b, cmp) => {
                let (x, y) = (u32::from(self.word(a)), self.w(b));
                match cmp {
                    super::program::Cmp::Eq => x == y,
                    super::program::Cmp::Ne => x != y,
                    super::program::Cmp::Ge => x >= y,
                    super::program::Cmp::Lt => x < y,
                }
            }
        }
    }
}
