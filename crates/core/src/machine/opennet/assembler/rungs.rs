//! The rung structure of spec §5.1 checked over the instructions, and resolved once they
//! assemble: each JMP's JEND, each MCS's MCR, and where each rung opens.

use super::STACK_DEPTH;
use crate::machine::opennet::program::{Op, Program};

/// What the rung check needs of an instruction.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    /// LOD, LODN and the compare contacts.
    Load,
    Logic,
    AndOrLod,
    Bps,
    Brd,
    Bpp,
    Output,
    /// A counter or shift register: it takes this many LOD blocks and ends its rung.
    Boxed(u32),
    /// MCS or JMP: an output that ends its rung.
    Opener,
    /// MCR or JEND: alone between rungs.
    Closer,
    Nop,
    End,
}

fn kind_of(mnemonic: &str) -> Kind {
    match mnemonic {
        "LOD" | "LODN" | "CC=" | "CC>=" | "DC=" | "DC>=" => Kind::Load,
        "AND" | "ANDN" | "OR" | "ORN" | "SOTU" | "SOTD" => Kind::Logic,
        "ANDLOD" | "ORLOD" => Kind::AndOrLod,
        "BPS" => Kind::Bps,
        "BRD" => Kind::Brd,
        "BPP" => Kind::Bpp,
        "CNT" => Kind::Boxed(2),
        "CDP" | "CUD" | "SFR" | "SFRN" => Kind::Boxed(3),
        "MCS" | "JMP" => Kind::Opener,
        "MCR" | "JEND" => Kind::Closer,
        "NOP" => Kind::Nop,
        "END" => Kind::End,
        _ => Kind::Output,
    }
}

/// Stands in `seq` for a line that did not assemble: what it would have done to the rung is
/// unknown, so the rung checks start afresh after it rather than report what follows from it.
pub(super) const NOT_ASSEMBLED: &str = "?";

/// The rung-structure check of spec §5.1 over the known instructions: (line, mnemonic).
pub(super) fn rungs(
    seq: &[(usize, &'static str)],
    end_line: Option<usize>,
) -> Vec<(usize, String)> {
    let mut errors = Vec::new();
    let (mut blocks, mut branches) = (0u32, 0u32);
    // The kind of the last instruction other than NOP (NOP may stand anywhere).
    let mut previous: Option<Kind> = None;
    // The first logic instruction since the last output (logic that drives nothing).
    let mut dangling: Option<usize> = None;
    // MCS and JMP not yet closed: the first of each since its last closer.
    let (mut open_mcs, mut open_jmp): (Option<usize>, Option<usize>) = (None, None);
    for &(line, mnemonic) in seq {
        if mnemonic == NOT_ASSEMBLED {
            (blocks, branches, dangling) = (0, 0, None);
            previous = Some(Kind::Output);
            continue;
        }
        let kind = kind_of(mnemonic);
        if kind == Kind::End {
            break;
        }
        if kind == Kind::Nop {
            continue;
        }
        let mut error = None;
        if previous.is_none() && kind != Kind::Load {
            error = Some("a program starts with LOD or LODN".to_string());
        }
        let rung_open = matches!(
            previous,
            Some(Kind::Load | Kind::Logic | Kind::AndOrLod | Kind::Bps | Kind::Brd | Kind::Bpp)
        );
        if matches!(previous, Some(Kind::Boxed(_) | Kind::Opener))
            && !matches!(kind, Kind::Load | Kind::Closer)
        {
            error.get_or_insert_with(|| "after a counter, shift register, MCS or JMP a new rung starts (LOD), or MCR, JEND, NOP or END follows".into());
        }
        match kind {
            Kind::Load => {
                let rung_start = !rung_open;
                if rung_start {
                    if branches > 0 {
                        error.get_or_insert_with(|| {
                            "a new rung starts while BPS is not closed by BPP".into()
                        });
                    }
                    blocks = 0;
                    branches = 0;
                } else {
                    blocks += 1;
                    if blocks > STACK_DEPTH {
                        error.get_or_insert_with(|| "more than 8 LOD blocks open".into());
                    }
                }
                dangling.get_or_insert(line);
            }
            Kind::Logic => {
                dangling.get_or_insert(line);
            }
            Kind::AndOrLod => {
                if blocks == 0 {
                    error.get_or_insert_with(|| format!("{mnemonic} with no LOD block to combine"));
                } else {
                    blocks -= 1;
                }
                dangling.get_or_insert(line);
            }
            Kind::Bps => {
                branches += 1;
                if branches > STACK_DEPTH {
                    error.get_or_insert_with(|| "more than 8 BPS open".into());
                }
                dangling.get_or_insert(line);
            }
            Kind::Brd | Kind::Bpp => {
                if branches == 0 {
                    error.get_or_insert_with(|| format!("{mnemonic} without BPS"));
                } else if kind == Kind::Bpp {
                    branches -= 1;
                }
                dangling.get_or_insert(line);
            }
            Kind::Output | Kind::Opener => {
                if blocks > 0 {
                    error.get_or_insert_with(|| {
                        "an output while LOD blocks are not combined (ANDLOD/ORLOD)".into()
                    });
                }
                if mnemonic == "MCS" {
                    open_mcs.get_or_insert(line);
                } else if mnemonic == "JMP" {
                    open_jmp.get_or_insert(line);
                }
                dangling = None;
            }
            Kind::Boxed(inputs) => {
                if blocks + 1 != inputs {
                    error.get_or_insert_with(|| {
                        format!(
                            "{mnemonic} takes {inputs} inputs, one LOD block each; it has {}",
                            blocks + 1
                        )
                    });
                }
                blocks = 0;
                dangling = None;
            }
            Kind::Closer => {
                if rung_open {
                    error.get_or_insert_with(|| {
                        format!(
                            "{mnemonic} while a rung's logic is open: it stands alone between rungs"
                        )
                    });
                } else if branches > 0 {
                    error.get_or_insert_with(|| {
                        format!("{mnemonic} while BPS is not closed by BPP")
                    });
                }
                let opener = if mnemonic == "MCR" {
                    &mut open_mcs
                } else {
                    &mut open_jmp
                };
                if opener.take().is_none() {
                    let what = if mnemonic == "MCR" {
                        "MCR with no MCS since the previous MCR"
                    } else {
                        "JEND with no JMP since the previous JEND"
                    };
                    error.get_or_insert_with(|| what.into());
                }
                (blocks, branches) = (0, 0);
                dangling = None;
            }
            Kind::Nop | Kind::End => {}
        }
        if let Some(e) = error {
            errors.push((line, e));
        }
        previous = Some(kind);
    }
    let last_line = end_line.or(seq.last().map(|(l, _)| *l));
    if branches > 0
        && let Some(l) = last_line
    {
        errors.push((l, "the program ends with BPS not closed by BPP".into()));
    }
    if let Some(l) = dangling {
        errors.push((l, "logic that drives nothing: no output follows".into()));
    }
    if let Some(l) = open_mcs {
        errors.push((l, "MCS not closed by a later MCR".into()));
    }
    if let Some(l) = open_jmp {
        errors.push((l, "JMP not closed by a later JEND".into()));
    }
    errors
}

/// Each JMP's JEND and each MCS's MCR (the first after it), and whether each LOD starts a
/// rung.
pub(super) fn resolve(program: &mut Program) {
    let n = program.instrs.len();
    let (mut next_jend, mut next_mcr) = (u32::MAX, u32::MAX);
    for i in (0..n).rev() {
        match program.instrs[i].op {
            Op::Jend => next_jend = i as u32,
            Op::Mcr => next_mcr = i as u32,
            Op::Jmp(_) => program.instrs[i].op = Op::Jmp(next_jend),
            Op::Mcs(_) => program.instrs[i].op = Op::Mcs(next_mcr),
            _ => {}
        }
    }
    let mut opens = Vec::with_capacity(n);
    let mut after_output = true;
    for instr in &program.instrs {
        opens.push(after_output);
        match instr.op {
            Op::Nop => {}
            op => after_output = op.is_output() || matches!(op, Op::Mcr | Op::Jend),
        }
    }
    program.opens = opens;
    program.marks_code = program
        .instrs
        .iter()
        .any(|i| matches!(i.op, Op::Mcs(_) | Op::Jmp(_)));
}
