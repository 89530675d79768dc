//! The rung checks of spec §2: the boolean stack, outputs and boxes, and one box per timer or
//! counter number.

use super::STACK_LEVELS;
use crate::machine::dl205::program::{Bit, CounterKind, Instr, Kind, Op, box_shape};

/// One box per timer or counter number; a two-word box takes n and n + 1 (spec §2).
fn boxes_once(instrs: &[Instr], errors: &mut Vec<(usize, String)>) {
    let mut owner: std::collections::HashMap<Bit, usize> = std::collections::HashMap::new();
    for ins in instrs {
        let (kind, n) = match ins.op {
            Op::Timer(_, n, _) => (Kind::T, n),
            Op::Counter(_, n, _) => (Kind::Ct, n),
            _ => continue,
        };
        let words = box_shape(&ins.op).map_or(1, |(w, _)| w);
        for k in n..n + words {
            let b = Bit { kind, n: k };
            if let Some(&line) = owner.get(&b) {
                let name = crate::machine::dl205::program::bit_name(b);
                errors.push((
                    ins.line,
                    format!("{name} is already used by the box on line {line}: one box per number"),
                ));
                break;
            }
            owner.insert(b, ins.line);
        }
    }
}

/// The rung checks of spec §2: (line, message).
pub(super) fn rungs(instrs: &[Instr]) -> Vec<(usize, String)> {
    let mut errors = Vec::new();
    let mut levels: usize = 0;
    let mut in_rung = false;
    let mut has_output = false;
    let mut end_line = None;
    // The multi-input box that ended the rung: only a new rung, NOP or END may follow.
    let mut after_box: Option<String> = None;
    for ins in instrs {
        match ins.op {
            Op::Nop => continue,
            op if op.is_standalone() => {
                if in_rung && !has_output {
                    errors.push((
                        ins.line,
                        format!("a rung with no output before {}", ins.mnemonic),
                    ));
                }
                in_rung = false;
                if op == Op::End && end_line.is_none() {
                    end_line = Some(ins.line);
                }
            }
            Op::Str(_) => {
                // A new rung when there is none or this one has its output; a branch otherwise.
                if !in_rung || has_output {
                    in_rung = true;
                    has_output = false;
                    levels = 0;
                }
                levels += 1;
                if levels > STACK_LEVELS {
                    errors.push((ins.line, "more than 8 levels on the boolean stack".into()));
                }
            }
            Op::And(_) | Op::Or(_) | Op::Not => {
                if after_box.is_some() {
                    errors.push((
                        ins.line,
                        format!(
                            "{} after {}: it ends its rung; start a new rung with STR",
                            ins.mnemonic,
                            after_box.unwrap_or_default()
                        ),
                    ));
                } else if !in_rung {
                    errors.push((
                        ins.line,
                        format!("{} needs a rung: start it with STR", ins.mnemonic),
                    ));
                }
            }
            Op::AndStr | Op::OrStr => {
                if !in_rung {
                    errors.push((
                        ins.line,
                        format!("{} needs a rung: start it with STR", ins.mnemonic),
                    ));
                } else if levels < 2 {
                    errors.push((
                        ins.line,
                        format!("{} needs two levels on the boolean stack", ins.mnemonic),
                    ));
                } else {
                    levels -= 1;
                }
            }
            op => {
                let legs = box_shape(&op).map_or(1, |(_, legs)| legs);
                if !in_rung {
                    errors.push((
                        ins.line,
                        "needs a rung condition: start the rung with a contact, e.g. STR SP1"
                            .into(),
                    ));
                } else if let Some(boxed) = &after_box {
                    errors.push((
                        ins.line,
                        format!(
                            "{} after {boxed}: it ends its rung; start a new rung with STR",
                            ins.mnemonic
                        ),
                    ));
                } else if legs > 1 {
                    // Each leg is its own STR, first leg first, and the box is the rung's
                    // first output (spec §2).
                    if has_output {
                        errors.push((
                            ins.line,
                            format!("{} must be the first output of its rung", ins.mnemonic),
                        ));
                    } else if levels != legs {
                        let names = match op {
                            Op::Counter(CounterKind::Udc, ..) => "up, down and reset",
                            Op::Counter(..) => "count and reset",
                            _ => "enable and reset",
                        };
                        errors.push((ins.line, format!("{} takes {legs} inputs ({names}), each started by its own STR; found {levels}", ins.mnemonic)));
                    }
                    has_output = true;
                } else {
                    if levels != 1 {
                        errors.push((
                            ins.line,
                            "branches are not merged (ANDSTR/ORSTR) before this output".into(),
                        ));
                    }
                    has_output = true;
                }
                // A multi-input box, like FOR (whose body starts with a rung), ends its rung.
                if legs > 1 || matches!(op, Op::For(..)) {
                    after_box = Some(ins.mnemonic.clone());
                }
                continue;
            }
        }
        after_box = None;
    }
    boxes_once(instrs, &mut errors);
    if end_line.is_none() {
        let line = instrs.last().map_or(1, |i| i.line);
        errors.push((line, "no END: a DL205 program ends with END".into()));
    }
    errors
}
