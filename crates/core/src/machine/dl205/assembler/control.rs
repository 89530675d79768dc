//! Program control (spec §2): the blocks (main part, stages, subroutines), and the targets of
//! GOTO, GTS, FOR … NEXT, SG and JMP checked and resolved.

use crate::machine::dl205::program::{Instr, Op};

/// The blocks of spec §2 (main part, stages, subroutines after END) and the program-control
/// instructions checked against them; on success their targets are resolved to instruction
/// indices: GOTO → its LBL, GTS → its SBR, FOR ↔ NEXT, SG → the next SG/ISG/END, JMP → the
/// enclosing stage.
pub(super) fn control(instrs: &mut [Instr]) -> Vec<(usize, String)> {
    use std::collections::HashMap;
    let mut errors = Vec::new();
    let n = instrs.len();
    let Some(end) = instrs.iter().position(|i| i.op == Op::End) else {
        return errors;
    };
    // Which block each instruction is in: 0 the main part, 1 + i the stage whose SG/ISG is at
    // i, n + 1 + i the subroutine whose SBR is at i; None: outside any (after END).
    let mut block: Vec<Option<usize>> = vec![None; n];
    let mut labels: HashMap<u16, usize> = HashMap::new();
    let mut subroutines: HashMap<u16, usize> = HashMap::new();
    let mut stages: HashMap<u32, usize> = HashMap::new();
    let mut stage = None;
    let mut sub: Option<usize> = None;
    for i in 0..n {
        let ins = &instrs[i];
        if i <= end {
            match ins.op {
                Op::Sg { stage: s, .. } => {
                    if let Some(&first) = stages.get(&s) {
                        errors.push((
                            ins.line,
                            format!(
                                "stage S{s:o} already has its SG/ISG on line {}",
                                instrs[first].line
                            ),
                        ));
                    }
                    stages.insert(s, i);
                    stage = Some(i);
                }
                Op::Rt | Op::Rtc => errors.push((
                    ins.line,
                    format!(
                        "{} outside a subroutine: subroutines come after END, SBR … RT",
                        ins.mnemonic
                    ),
                )),
                Op::Sbr(_) => errors.push((
                    ins.line,
                    "SBR before END: subroutines come after the main program's END".into(),
                )),
                _ => {}
            }
            block[i] = Some(stage.map_or(0, |s| 1 + s));
            continue;
        }
        match ins.op {
            Op::Sbr(k) => {
                if sub.is_some() {
                    errors.push((
                        ins.line,
                        "SBR inside a subroutine: end the one before with RT".into(),
                    ));
                }
                if let Some(&first) = subroutines.get(&k) {
                    errors.push((
                        ins.line,
                        format!(
                            "SBR K{k:X} is already defined on line {}",
                            instrs[first].line
                        ),
                    ));
                }
                subroutines.insert(k, i);
                sub = Some(i);
            }
            Op::End => errors.push((
                ins.line,
                "END in a subroutine: a subroutine ends with RT".into(),
            )),
            Op::Sg { .. } => errors.push((
                ins.line,
                format!(
                    "{} in a subroutine: stages belong to the main program",
                    ins.mnemonic
                ),
            )),
            _ if sub.is_none() => {
                errors.push((
                    ins.line,
                    format!(
                        "{} after END: only subroutines (SBR … RT) may follow END",
                        ins.mnemonic
                    ),
                ));
            }
            _ => {}
        }
        block[i] = sub.map(|s| n + 1 + s);
        if ins.op == Op::Rt {
            sub = None;
        }
    }
    if let Some(open) = sub {
        errors.push((instrs[open].line, "SBR without RT".into()));
    }

    // Labels, FOR … NEXT and master-line levels, block by block in program order.
    let mut open_for: Option<usize> = None;
    let mut in_loop: Vec<Option<usize>> = vec![None; n];
    let mut level = 0u8;
    for i in 0..n {
        let starts_block = i == 0 || block[i] != block[i - 1];
        if starts_block {
            if let Some(f) = open_for.take() {
                errors.push((instrs[f].line, "FOR without NEXT in its block".into()));
            }
            level = 0;
        }
        let ins = &instrs[i];
        match ins.op {
            Op::Lbl(k) => {
                if let Some(&first) = labels.get(&k) {
                    errors.push((
                        ins.line,
                        format!(
                            "LBL K{k:X} is already defined on line {}",
                            instrs[first].line
                        ),
                    ));
                }
                labels.insert(k, i);
            }
            Op::For(..) => {
                if open_for.is_some() {
                    errors.push((ins.line, "FOR inside a FOR loop: loops do not nest".into()));
                } else {
                    open_for = Some(i);
                }
            }
            Op::Next(_) => match open_for.take() {
                Some(f) => {
                    in_loop[f] = Some(f);
                    in_loop[i] = Some(f);
                    if let Op::For(c, _) = instrs[f].op {
                        instrs[f].op = Op::For(c, i as u32);
                    }
                    instrs[i].op = Op::Next(f as u32);
                    continue;
                }
                None => errors.push((ins.line, "NEXT without FOR".into())),
            },
            Op::Sbr(_) | Op::Sg { .. } => level = 0,
            Op::Mls(k) => {
                if k != level + 1 {
                    errors.push((
                        ins.line,
                        format!(
                            "MLS K{k} must follow level {}: the current level is {level}",
                            k - 1
                        ),
                    ));
                }
                level = k;
            }
            Op::Mlr(k) => {
                if k >= level {
                    errors.push((
                        ins.line,
                        format!("MLR K{k} must be below the current level {level}"),
                    ));
                }
                level = k.min(level);
            }
            _ => {}
        }
        in_loop[i] = open_for;
    }
    if let Some(f) = open_for {
        errors.push((instrs[f].line, "FOR without NEXT in its block".into()));
    }

    // Jumps, calls and stage jumps.
    let mut calls: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
    for i in 0..n {
        let ins = &instrs[i];
        match ins.op {
            Op::Goto(k) => match labels.get(&(k as u16)) {
                None => errors.push((ins.line, format!("GOTO K{k:X}: no LBL K{k:X}"))),
                Some(&to) if to <= i => errors.push((
                    ins.line,
                    format!(
                        "GOTO K{k:X} jumps backwards (to line {}): GOTO only jumps forward",
                        instrs[to].line
                    ),
                )),
                Some(&to) if block[to] != block[i] || in_loop[to] != in_loop[i] => {
                    errors.push((ins.line, format!("GOTO K{k:X} leaves its block (stage, subroutine or FOR loop): LBL K{k:X} is on line {}", instrs[to].line)));
                }
                Some(&to) => instrs[i].op = Op::Goto(to as u32),
            },
            Op::Gts(k) => match subroutines.get(&(k as u16)) {
                None => errors.push((ins.line, format!("GTS K{k:X}: no SBR K{k:X}"))),
                Some(&to) => {
                    let caller = block[i]
                        .filter(|&b| b > n)
                        .map_or(usize::MAX, |b| b - n - 1);
                    calls.entry(caller).or_default().push((to, i));
                    instrs[i].op = Op::Gts(to as u32);
                }
            },
            Op::Jmp { to, .. } | Op::Njmp { to, .. } => {
                let own = match block[i] {
                    Some(b) if b >= 1 && b <= n => match instrs[b - 1].op {
                        Op::Sg { stage, .. } => Some(stage),
                        _ => None,
                    },
                    _ => None,
                };
                match own {
                    None => errors.push((
                        ins.line,
                        format!(
                            "{} outside a stage: it belongs after an SG or ISG",
                            ins.mnemonic
                        ),
                    )),
                    Some(_) if !stages.contains_key(&to) => errors.push((
                        ins.line,
                        format!("{} S{to:o}: no SG or ISG S{to:o}", ins.mnemonic),
                    )),
                    Some(own) => {
                        instrs[i].op = if matches!(ins.op, Op::Jmp { .. }) {
                            Op::Jmp { to, own }
                        } else {
                            Op::Njmp { to, own }
                        };
                    }
                }
            }
            Op::Sg { stage, initial, .. } => {
                let next = (i + 1..n)
                    .find(|&j| matches!(instrs[j].op, Op::Sg { .. } | Op::End))
                    .unwrap_or(end);
                instrs[i].op = Op::Sg {
                    stage,
                    initial,
                    next: next as u32,
                };
            }
            _ => {}
        }
    }
    // Calls: no recursion, at most 8 deep (so a run never faults).
    fn depth(
        sub: usize,
        calls: &std::collections::HashMap<usize, Vec<(usize, usize)>>,
        path: &mut Vec<usize>,
    ) -> Result<usize, usize> {
        if path.contains(&sub) {
            return Err(sub);
        }
        path.push(sub);
        let mut deepest = 0;
        for &(callee, _) in calls.get(&sub).map_or(&[][..], |v| v.as_slice()) {
            deepest = deepest.max(depth(callee, calls, path)? + 1);
        }
        path.pop();
        Ok(deepest)
    }
    for (&caller, list) in &calls {
        for &(callee, at) in list {
            let line = instrs[at].line;
            let mut path = if caller == usize::MAX {
                Vec::new()
            } else {
                vec![caller]
            };
            match depth(callee, &calls, &mut path) {
                Err(_) => errors.push((
                    line,
                    format!(
                        "{}: recursion: a subroutine may not call itself, directly or not",
                        instrs[at].text
                    ),
                )),
                Ok(d) if caller == usize::MAX && d + 1 > crate::machine::dl205::CALL_DEPTH => {
                    errors.push((
                        line,
                        format!(
                            "{}: calls nested {} deep (at most {})",
                            instrs[at].text,
                            d + 1,
                            crate::machine::dl205::CALL_DEPTH
                        ),
                    ));
                }
                Ok(_) => {}
            }
        }
    }
    errors.sort();
    errors.dedup();
    errors
}
