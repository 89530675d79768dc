//! Property tests: each arithmetic operation against a plain i64/i128 reference written here,
//! and random queue sequences against a `VecDeque` model.

use crate::common;
use std::collections::VecDeque;

use common::{flags, machine, reg, run};
use proptest::prelude::*;
use servoscope_core::machine::{Machine, MachineView, RunState};

/// Reduce any integer to the signed 32-bit register it would wrap to.
fn wrap(v: i128) -> i32 {
    let m = v.rem_euclid(1 << 32);
    if m >= 1 << 31 {
        (m - (1 << 32)) as i32
    } else {
        m as i32
    }
}
fn word_hi(v: i32) -> i64 {
    (i64::from(v).rem_euclid(1 << 32)) / 65536
}
fn word_lo(v: i32) -> i64 {
    i64::from(v).rem_euclid(65536)
}
fn signed16(w: i64) -> i64 {
    if w >= 32768 { w - 65536 } else { w }
}
fn unsigned(v: i32) -> i128 {
    i128::from(v).rem_euclid(1 << 32)
}
/// Division truncated toward zero, remainder with the dividend's sign, in plain arithmetic.
fn trunc_div(n: i64, d: i64) -> (i64, i64) {
    let q = (n.abs() / d.abs()) * if (n < 0) != (d < 0) { -1 } else { 1 };
    (q, n - q * d)
}

/// Reference for `CLD op, 25, 26, d` with R26 = a. `None`: the operation faults.
fn ext_reference(op: &str, a: i32, d: i32) -> Option<i32> {
    let (a64, d64) = (i64::from(a), i64::from(d));
    let (a128, d128) = (i128::from(a), i128::from(d));
    Some(match op {
        "COPY" => a,
        "ABS" => wrap(a128.abs()),
        "NEG" => wrap(-a128),
        "ADD" => wrap(a128 + d128),
        "SUB" => wrap(a128 - d128),
        "SUB_REV" => wrap(d128 - a128),
        "ADD_HI" => wrap(i128::from(signed16(word_hi(a))) + d128),
        "ADD_LO" => wrap(i128::from(signed16(word_lo(a))) + d128),
        "AND" => wrap(unsigned(a) & unsigned(d)),
        "OR" => wrap(unsigned(a) | unsigned(d)),
        "XOR" => wrap(unsigned(a) ^ unsigned(d)),
        "MAX" => a64.max(d64) as i32,
        "MIN" => a64.min(d64) as i32,
        "SEXT_HI" => signed16(word_hi(a)) as i32,
        "SEXT_LO" => signed16(word_lo(a)) as i32,
        "PACK_LO_LO" => wrap(i128::from(word_lo(a) * 65536 + word_lo(d))),
        "PACK_HI_LO" => wrap(i128::from(word_hi(a) * 65536 + word_lo(d))),
        "PACK_HI_HI" => wrap(i128::from(word_hi(a) * 65536 + word_hi(d))),
        "MULT_S" => wrap(a128 * d128),
        "MULT_U" => wrap(unsigned(a) * unsigned(d)),
        "MULT_S64_SHR16" => wrap((a128 * d128).div_euclid(65536)),
        "DIV" | "MOD" | "DIV_REV" | "MOD_REV" => {
            let (n, div) = if op.ends_with("REV") {
                (d64, signed16(word_lo(a)))
            } else {
                (a64, signed16(word_lo(d)))
            };
            if div == 0 || (n == i64::from(i32::MIN) && div == -1) {
                return None;
            }
            let (q, r) = trunc_div(n, div);
            if op.starts_with("DIV") {
                q as i32
            } else {
                r as i32
            }
        }
        _ => unreachable!("{op}"),
    })
}

const EXT_OPS: &[&str] = &[
    "COPY",
    "ABS",
    "NEG",
    "ADD",
    "SUB",
    "SUB_REV",
    "ADD_HI",
    "ADD_LO",
    "AND",
    "OR",
    "XOR",
    "MAX",
    "MIN",
    "SEXT_HI",
    "SEXT_LO",
    "PACK_LO_LO",
    "PACK_HI_LO",
    "PACK_HI_HI",
    "MULT_S",
    "MULT_U",
    "MULT_S64_SHR16",
    "DIV",
    "MOD",
    "DIV_REV",
    "MOD_REV",
];

/// Values that reach the edges often: extremes, small numbers, 16-bit boundaries.
fn value() -> impl Strategy<Value = i32> {
    prop_oneof![
        any::<i32>(),
        -70_000i32..70_000,
        prop::sample::select(vec![
            0,
            1,
            -1,
            i32::MIN,
            i32::MAX,
            0xFFFF,
            0x8000,
            -0x8000,
            0x10000,
            -65536
        ]),
    ]
}

fn expected_flags(v: i32) -> (bool, bool, bool) {
    (v == 0, v > 0, v < 0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn cld_and_clx_match_the_reference(op in prop::sample::select(EXT_OPS), a in value(), d in value()) {
        let cld = run(&format!("WRP 26, {a}\nCLD {op}, 25, 26, {}", d as u32));
        let clx = run(&format!("WRP 26, {a}\nWRP 27, {d}\nCLX {op}, 25, 26, 27"));
        for m in [&cld, &clx] {
            match ext_reference(op, a, d) {
                Some(want) => {
                    prop_assert_eq!(m.run_state(), RunState::Ended);
                    prop_assert_eq!(reg(m, 25), want, "{} a={} d={}", op, a, d);
                    prop_assert_eq!(flags(m), expected_flags(want));
                }
                None => {
                    prop_assert_eq!(m.run_state(), RunState::Faulted);
                    prop_assert_eq!(reg(m, 25), 0, "a fault writes nothing");
                }
            }
        }
    }

    #[test]
    fn clc_matches_the_reference(op in prop::sample::select(vec![
        "ADD", "SUB", "SUB_REV", "MULT_S", "MULT_U", "DIV", "MOD", "MAX", "MIN", "AND", "OR", "XOR",
        "ADD_HI", "ADD_LO", "SEXT_HI", "SEXT_LO", "COPY_WORD_HI_ACC",
    ]), acc in value(), x in value()) {
        let m = run(&format!("WRP 10, {acc}\nWRP 11, {x}\nCLC {op}, 11"));
        // CLC on the accumulator is CLD with reg1 = Acc and d = R[reg] for these operations.
        let want = match op {
            "ADD_HI" => Some(wrap(i128::from(acc) + i128::from(signed16(word_hi(x))))),
            "ADD_LO" => Some(wrap(i128::from(acc) + i128::from(signed16(word_lo(x))))),
            "SEXT_HI" | "SEXT_LO" => ext_reference(op, x, 0),
            "SUB_REV" => Some(wrap(i128::from(x) - i128::from(acc))),
            "COPY_WORD_HI_ACC" => Some(wrap(i128::from(word_lo(x) * 65536 + word_lo(acc)))),
            _ => ext_reference(op, acc, x),
        };
        match want {
            Some(want) => {
                prop_assert_eq!(reg(&m, 10), want, "{} acc={} x={}", op, acc, x);
                prop_assert_eq!(flags(&m), expected_flags(want));
            }
            None => {
                prop_assert_eq!(m.run_state(), RunState::Faulted);
                prop_assert_eq!(reg(&m, 10), acc);
            }
        }
    }

    #[test]
    fn clc_register_ops_match_the_reference(x in value()) {
        let m = run(&format!(
            "WRP 11, {x}\nCLC ABS, 11\nWRP 12, {x}\nCLC NEG, 12\nWRP 13, {x}\nCLC INC, 13\nWRP 14, {x}\nCLC DEC, 14\n\
             WRP 15, {x}\nCLC SHL, 15\nWRP 16, {x}\nCLC SHR_S, 16\nWRP 17, {x}\nCLC SHR_U, 17"
        ));
        let x128 = i128::from(x);
        prop_assert_eq!(reg(&m, 11), wrap(x128.abs()));
        prop_assert_eq!(reg(&m, 12), wrap(-x128));
        prop_assert_eq!(reg(&m, 13), wrap(x128 + 1));
        prop_assert_eq!(reg(&m, 14), wrap(x128 - 1));
        prop_assert_eq!(reg(&m, 15), wrap(x128 * 2));
        prop_assert_eq!(reg(&m, 16), wrap(x128.div_euclid(2)));
        prop_assert_eq!(reg(&m, 17), wrap(unsigned(x) / 2));
    }

    #[test]
    fn mult_u64_and_div_u64_match_128_bit_arithmetic(a in any::<u32>(), d in any::<u32>(), hi in any::<u32>(), lo in any::<u32>()) {
        let m = run(&format!("WRP 26, {a}\nCLD MULT_U64, 30, 26, {d}"));
        let p = u128::from(a) * u128::from(d);
        prop_assert_eq!((u128::from(m.reg(30) as u32) << 32) | u128::from(m.reg(31) as u32), p);
        prop_assert_eq!(flags(&m), (p == 0, p != 0, false));

        let m = run(&format!("WRP 26, {hi}\nWRP 27, {lo}\nCLD DIV_U64, 25, 26, {d}"));
        let n = (u128::from(hi) << 32) | u128::from(lo);
        if d == 0 || n / u128::from(d) > u128::from(u32::MAX) {
            prop_assert_eq!(m.run_state(), RunState::Faulted);
            prop_assert_eq!(m.reg(25), 0);
        } else {
            let q = n / u128::from(d);
            prop_assert_eq!(u128::from(m.reg(25) as u32), q);
            prop_assert_eq!(flags(&m), (q == 0, q != 0, false));
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum QOp {
    PushHead(i32),
    PushTail(i32),
    PopHead,
    PopTail,
    Read(i32),
}

fn qop() -> impl Strategy<Value = QOp> {
    prop_oneof![
        (-1000i32..1000).prop_map(QOp::PushHead),
        (-1000i32..1000).prop_map(QOp::PushTail),
        Just(QOp::PopHead),
        Just(QOp::PopTail),
        (-10i32..10).prop_map(QOp::Read),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// The model: the back of the deque is the head (newest), the front the tail (oldest).
    #[test]
    fn queues_behave_like_a_deque(size in 1usize..9, ops in prop::collection::vec(qop(), 1..60)) {
        let mut text = format!("CLD Q_INIT, 10, 40, {size}\n");
        for op in &ops {
            text.push_str(&match op {
                QOp::PushHead(v) => format!("CLD Q_PUSH_HEAD, 12, 40, {v}\n"),
                QOp::PushTail(v) => format!("CLD Q_PUSH_TAIL, 12, 40, {v}\n"),
                QOp::PopHead => "CLD Q_POP_HEAD, 12, 40, 0\n".to_string(),
                QOp::PopTail => "CLD Q_POP_TAIL, 12, 40, 0\n".to_string(),
                QOp::Read(n) => format!("CLD Q_READ, 12, 40, {n}\n"),
            });
        }
        let mut m = machine(&text);
        m.step_command(10);
        let mut model: VecDeque<i32> = VecDeque::new();
        for op in &ops {
            let before = m.reg(12);
            m.step_command(10);
            let expected: Option<i32> = match *op {
                QOp::PushHead(v) if model.len() < size => { model.push_back(v); Some((size - model.len()) as i32) }
                QOp::PushTail(v) if model.len() < size => { model.push_front(v); Some((size - model.len()) as i32) }
                QOp::PopHead => model.pop_back(),
                QOp::PopTail => model.pop_front(),
                QOp::Read(n) if n >= 0 => model.len().checked_sub(1 + n as usize).map(|i| model[i]),
                QOp::Read(n) => model.get((-n - 1) as usize).copied(),
                _ => None,
            };
            match expected {
                Some(v) => {
                    prop_assert_eq!(m.reg(12), v, "{:?}", op);
                    prop_assert_eq!(flags(&m), (true, false, false));
                }
                None => {
                    prop_assert_eq!(m.reg(12), before, "failed op leaves the result register alone");
                    prop_assert_eq!(flags(&m), (false, false, true));
                }
            }
            let q = m.queues();
            let header = q[0].header.as_ref().expect("queue stays valid");
            prop_assert_eq!(header.len, model.len());
            prop_assert_eq!(&header.items, &model.iter().copied().collect::<Vec<_>>());
        }
    }
}
