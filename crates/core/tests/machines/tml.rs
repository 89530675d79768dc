//! TML against its spec (`tml.md`) and the vendor text (`tml-arithmetic.txt`): every worked
//! example, the arithmetic against an i128 reference, PREG, division, the call stack, events and
//! WAIT! tick by tick, the motion model, assembler errors and the runner.

fn errors(src: &str) -> Vec<String> {
    crate::common::error_texts(machine(src))
}

use proptest::prelude::*;
use servoscope_core::machine::tml::dialect::machine;
use servoscope_core::machine::tml::{Tml, d};
use servoscope_core::machine::{Machine, MachineView, Pos, RunState};

fn run(src: &str) -> Tml {
    let mut m = machine(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    m.run_until(1_000_000, |_| false);
    m
}

fn var(m: &Tml, name: &str) -> i64 {
    let i = m
        .program
        .vars
        .iter()
        .position(|v| v.name == name)
        .unwrap_or_else(|| panic!("variable {name}"));
    match m.program.vars[i].ty {
        servoscope_core::machine::tml::Ty::Int | servoscope_core::machine::tml::Ty::Uint => {
            i64::from(m.vars[i] as u16 as i16)
        }
        _ => i64::from(m.vars[i] as i32),
    }
}

const DECLS: &str = "int int_var; int int_var2; int int_var1; long long_var; long long_var2; fixed fixed_var; fixed fixed_var2;\n";

// ---- The vendor text's examples (values worked out from its comments) -------------------

#[test]
fn vendor_addition_and_subtraction() {
    let m = run(&format!(
        "{DECLS}int_var = 5; int_var2 = 7; long_var = 1000; long_var2 = 70000; fixed_var = 1.5; fixed_var2 = 0.25;
int_var += 10; int_var += int_var2; long_var += -100; long_var += long_var2; fixed_var += 10.; fixed_var += fixed_var2;"
    ));
    assert_eq!(var(&m, "int_var"), 5 + 10 + 7);
    assert_eq!(var(&m, "long_var"), 1000 - 100 + 70000);
    // 1.5 + 10.0 + 0.25 = 11.75
    assert_eq!(var(&m, "fixed_var"), (11.75 * 65536.0) as i64);
    let m = run(&format!(
        "{DECLS}int_var = 5; int_var2 = 7; long_var = 1000; long_var2 = 70000; fixed_var = 1.5; fixed_var2 = 0.25;
int_var -= 10; int_var -= int_var2; long_var -= -100; long_var -= long_var2; fixed_var -= 10.; fixed_var -= fixed_var2;"
    ));
    assert_eq!(var(&m, "int_var"), 5 - 10 - 7);
    assert_eq!(var(&m, "long_var"), 1000 + 100 - 70000);
    assert_eq!(var(&m, "fixed_var"), (-8.75 * 65536.0) as i64);
}

#[test]
fn vendor_remark_a_16_bit_value_into_32_bit_data() {
    // Sign-extended into a long; the integer part of a fixed.
    let m = run(&format!(
        "{DECLS}int_var = -3; long_var = 10; fixed_var = 0.5; long_var += int_var; fixed_var += int_var;"
    ));
    assert_eq!(var(&m, "long_var"), 7);
    assert_eq!(var(&m, "fixed_var"), (-2.5 * 65536.0) as i64);
}

#[test]
fn vendor_multiplication_examples() {
    let m = run(&format!("{DECLS}long_var = 123456; long_var * -200 << 0;"));
    assert_eq!(m.preg_signed(), 123456 * -200);
    // fixed_var * 10 << 5 = fixed_var × 320, as 32.16 in PREG.
    let m = run(&format!("{DECLS}fixed_var = 2.5; fixed_var * 10 << 5;"));
    assert_eq!(m.preg_signed(), (2.5 * 65536.0) as i64 * 320);
    assert_eq!(
        m.raw(servoscope_core::machine::tml::program::Data::Pre(d::PRODH)) as i32,
        800
    );
    let m = run(&format!(
        "{DECLS}int_var1 = -7; int_var2 = 9; int_var1 * int_var2 >> 1;"
    ));
    assert_eq!(
        m.preg_signed(),
        (-63f64 / 2.0).floor() as i64,
        "floor: -31.5 → -32"
    );
    let m = run(&format!(
        "{DECLS}long_var = 1000001; int_var = 3; long_var * int_var >> 2;"
    ));
    assert_eq!(m.preg_signed(), 3000003 / 4);
    // long_var = PROD; long_var = PROD(H);
    let m = run(&format!(
        "{DECLS}long_var = 0x12345678; long_var * 0x100 << 0; long_var = PROD; long_var2 = PROD(H);"
    ));
    assert_eq!(var(&m, "long_var"), 0x3456_7800);
    assert_eq!(
        var(&m, "long_var2"),
        0x0012_3456,
        "bits 47..16 (spec §8: not 47..15)"
    );
}

#[test]
fn vendor_division_gives_fixed() {
    let m = run(&format!(
        "{DECLS}long_var = 10; int_var = 4; long_var /= int_var;"
    ));
    assert_eq!(var(&m, "long_var"), 163840, "2.5 as fixed 16.16");
    let m = run(&format!(
        "{DECLS}fixed_var = 10.; int_var = 4; fixed_var /= int_var;"
    ));
    assert_eq!(var(&m, "fixed_var"), 163840);
}

#[test]
fn vendor_shifts() {
    let m = run(&format!("{DECLS}long_var = 25; long_var << 3;"));
    assert_eq!(var(&m, "long_var"), 200);
    let m = run(&format!("{DECLS}int_var = -16; int_var >> 3;"));
    assert_eq!(var(&m, "int_var"), -2);
    assert_eq!(m.vars[0] & 0xFFFF, 0xFFFE);
    let m = run(&format!("{DECLS}int_var = 3; int_var * 7; PROD << 1;"));
    assert_eq!(m.preg_signed(), 42);
}

#[test]
fn vendor_srb_follows_the_stated_rule() {
    // Spec §8: (13 AND 0xFFFE) OR 0x2 = 14; the vendor's "12 (0xC)" forgets the OR mask.
    let m = run(&format!("{DECLS}int_var = 13; SRB int_var, 0xFFFE, 0x2;"));
    assert_eq!(var(&m, "int_var"), 14);
    let m = run(&format!("{DECLS}int_var = 13; SRBL int_var, 0xFFFE, 0x2;"));
    assert_eq!(var(&m, "int_var"), 14);
}

/// Issue #43 item 3: the words say bits were lost only when a set bit was dropped, and which.
#[test]
fn a_shifted_product_says_what_it_lost_and_only_then() {
    let explain = |src: &str| {
        let mut m = machine(src).unwrap_or_else(|e| panic!("{e:?}"));
        m.run_until(10, |_| false);
        (m.preg_signed(), m.explain_last().expect("an explanation"))
    };
    // 100000 × 3 = 300000 = 18750 × 16: the 4 bits shifted out are 0.
    let (preg, text) = explain("long l; int a; l = 100000; a = 3; l * a >> 4;");
    assert_eq!(preg, 18_750);
    assert!(!text.contains("lost"), "{text}");
    // 100001 × 3 = 300003 = 18750 × 16 + 3: the low bits 3 go.
    let (preg, text) = explain("long l; int a; l = 100001; a = 3; l * a >> 4;");
    assert_eq!(preg, 18_750);
    assert!(
        text.ends_with("(low bits 3 of 2^4 lost); product 300003"),
        "{text}"
    );
    // 1 × 1 << 1 = 2 fits in 48 bits.
    let (preg, text) = explain("int x; x = 1; x * 1 << 1;");
    assert_eq!(preg, 2);
    assert!(!text.contains("lost"), "{text}");
    // 2147483647 × 32767 = 70366596661249 < 2^46; << 4 passes 2^49, beyond PREG's signed 48.
    let (_, text) = explain("long l; int a; l = 2147483647; a = 32767; l * a << 4;");
    assert!(text.contains("(high bits beyond 48 lost)"), "{text}");
}

#[test]
fn the_issues_explanations() {
    let mut m = machine("int Var1; Var1 = 4694; Var1 * 293 << 12;").unwrap();
    m.run_until(10, |_| false);
    assert_eq!(m.preg, 0x0001_4FC6_E000);
    let text = m.explain_last().unwrap();
    assert!(
        text.contains("PREG = (Var1 4694 × 293) << 12 = 0x00014FC6E000"),
        "{text}"
    );
    let mut m =
        machine("long long_var; int int_var; long_var = 10; int_var = 4; long_var /= int_var;")
            .unwrap();
    m.run_until(10, |_| false);
    let text = m.explain_last().unwrap();
    assert!(
        text.contains("(10 × 65536) / 4 = 163840 = 2.5 (fixed)"),
        "{text}"
    );
    let mut m = machine("int int_var; int_var = 13; SRB int_var, 0xFFFE, 0x0002;").unwrap();
    m.run_until(10, |_| false);
    let text = m.explain_last().unwrap();
    assert!(
        text.contains("SRB int_var: (13 AND 0xFFFE) OR 0x0002 = 14"),
        "{text}"
    );
}

// ---- Widths, PREG, division ------------------------------------------------------------

#[test]
fn widths_wrap_and_halves_stay_apart() {
    let m = run(
        "int i; long l; i = 32767; i += 1; l = 0x0001FFFF; l(L) += 1; long h; h = 0x7FFFFFFF; h += 1;",
    );
    assert_eq!(var(&m, "i"), -32768);
    assert_eq!(var(&m, "l"), 0x0001_0000, "no carry into the high half");
    assert_eq!(var(&m, "h"), i64::from(i32::MIN));
    let m = run("int i; i = -32768; i = -i; long l; l = 0xFFFF; long k; k = 5; k += 0xFFFF;");
    assert_eq!(var(&m, "i"), -32768, "−(−32768) stays");
    assert_eq!(var(&m, "l"), 65535);
    assert_eq!(
        var(&m, "k"),
        5 + 65535,
        "an immediate added to a long is 32-bit"
    );
    let m = run("fixed f; f = 2; fixed g; g = 26.6667; fixed n; n = -0.75;");
    assert_eq!(
        var(&m, "f"),
        2 * 65536,
        "a whole number is the integer part"
    );
    assert_eq!(
        var(&m, "g"),
        1_747_629,
        "round(26.6667 × 65536) = round(1747628.85)"
    );
    assert_eq!(var(&m, "n"), -49152);
}

#[test]
fn fixed_literals_round_ties_away_from_zero() {
    // 0.5 / 65536 = 0.00000762939453125 is exactly half a unit.
    let m = run("fixed a; a = 0.00000762939453125; fixed b; b = -0.00000762939453125;");
    assert_eq!(var(&m, "a"), 1);
    assert_eq!(var(&m, "b"), -1);
}

#[test]
fn preg_wraps_at_48_bits_and_sign_extends() {
    let m = run("long l; l = 0x7FFFFFFF; l * 32767 << 15;");
    let exact = i128::from(i32::MAX) * 32767 * (1 << 15);
    let wrapped = (exact as u64) & ((1 << 48) - 1);
    assert_eq!(m.preg, wrapped);
    let m = run("int i; i = -1; i * 1;");
    assert_eq!(m.preg, (1 << 48) - 1, "−1 fills all 48 bits");
    assert_eq!(m.preg_signed(), -1);
    let m = run("int i; i = -8; i * 1; PROD >> 2; long a; a = PRODH;");
    assert_eq!(m.preg_signed(), -2);
    assert_eq!(var(&m, "a"), -1);
}

#[test]
fn division_truncates_saturates_and_survives_zero() {
    let m = run("long a; int b; a = -7; b = 2; a /= b;");
    assert_eq!(var(&m, "a"), -3 * 65536 - 32768, "−3.5 exactly");
    let m = run("fixed f; int b; f = 1.; b = 3; f /= b;");
    assert_eq!(var(&m, "f"), 21845, "65536 / 3 truncated");
    let m = run("long a; int b; a = 100000; b = 1; a /= b;");
    assert_eq!(var(&m, "a"), i64::from(i32::MAX), "saturated");
    let m = run("long a; int b; a = -100000; b = 1; a /= b;");
    assert_eq!(var(&m, "a"), i64::from(i32::MIN));
    let m = run("long a; int b; a = 5; a /= b; long c; c = -5; c /= b; long z; z = 0; z /= b;");
    assert_eq!(var(&m, "a"), i64::from(i32::MAX), "÷0 of a positive");
    assert_eq!(var(&m, "c"), i64::from(i32::MIN), "÷0 of a negative");
    assert_eq!(var(&m, "z"), i64::from(i32::MAX), "÷0 of zero (N ≥ 0)");
    assert_eq!(m.run_state(), RunState::Ended, "no fault");
}

// ---- Property tests against a plain reference -------------------------------------------

fn wrap16(v: i128) -> i64 {
    i64::from(v as u16 as i16)
}
fn wrap32(v: i128) -> i64 {
    i64::from(v as u32 as i32)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn addition_of_every_width_combination(a in any::<i16>(), b in any::<i16>(), la in any::<i32>(), lb in any::<i32>(), sub in any::<bool>()) {
        let op = if sub { "-=" } else { "+=" };
        let s: i128 = if sub { -1 } else { 1 };
        let src = format!(
            "int a; int b; long la; long lb; fixed fa; fixed fb; long lc; fixed fc;
             a = {a}; b = {b}; la = {la}; lb = {lb}; fa = la; fb = lb; lc = la; fc = fa;
             a {op} b; la {op} lb; fa {op} fb; lc {op} b; fc {op} b;"
        );
        let m = run(&src);
        prop_assert_eq!(var(&m, "a"), wrap16(i128::from(a) + s * i128::from(b)));
        prop_assert_eq!(var(&m, "la"), wrap32(i128::from(la) + s * i128::from(lb)));
        prop_assert_eq!(var(&m, "fa"), wrap32(i128::from(la) + s * i128::from(lb)));
        prop_assert_eq!(var(&m, "lc"), wrap32(i128::from(la) + s * i128::from(b)));
        prop_assert_eq!(var(&m, "fc"), wrap32(i128::from(la) + s * i128::from(b) * 65536));
    }

    #[test]
    fn multiplication_with_every_shift(a in any::<i32>(), b in any::<i16>(), n in 0u8..16, left in any::<bool>(), int_a in any::<i16>()) {
        let dir = if left { "<<" } else { ">>" };
        let m = run(&format!("long a; int b; a = {a}; b = {b}; a * b {dir} {n};"));
        let p = i128::from(a) * i128::from(b);
        let expected = if left { p << n } else { p >> n };
        prop_assert_eq!(m.preg, (expected as u64) & ((1 << 48) - 1));
        let m = run(&format!("int a; a = {int_a}; a * {b} {dir} {n};"));
        let p = i128::from(int_a) * i128::from(b);
        let expected = if left { p << n } else { p >> n };
        prop_assert_eq!(m.preg, (expected as u64) & ((1 << 48) - 1));
    }

    #[test]
    fn division_against_the_reference(a in any::<i32>(), b in any::<i16>(), fixed in any::<bool>()) {
        let ty = if fixed { "fixed" } else { "long" };
        let src = format!("long raw; {ty} x; int b; raw = {a}; x = raw; b = {b}; x /= b;");
        let m = run(&src);
        let n = if fixed { i128::from(a) } else { i128::from(a) * 65536 };
        let q = if b == 0 {
            if n >= 0 { i128::from(i32::MAX) } else { i128::from(i32::MIN) }
        } else {
            (n / i128::from(b)).clamp(i128::from(i32::MIN), i128::from(i32::MAX))
        };
        prop_assert_eq!(var(&m, "x"), q as i64);
    }

    #[test]
    fn shifts_on_16_and_32_bits(i in any::<i16>(), l in any::<i32>(), n in 0u8..16) {
        let m = run(&format!("int i; long l; int j; long k; i = {i}; l = {l}; j = i; k = l; i <<= {n}; l >>= {n}; j >> {n}; k << {n};"));
        prop_assert_eq!(var(&m, "i"), wrap16(i128::from(i) << n));
        prop_assert_eq!(var(&m, "l"), i64::from(l >> n));
        prop_assert_eq!(var(&m, "j"), i64::from(i >> n));
        prop_assert_eq!(var(&m, "k"), wrap32(i128::from(l) << n));
    }

    #[test]
    fn random_text_never_panics(text in "[ -~\\n]{0,200}") {
        let _ = machine(&text);
    }

    #[test]
    fn mutated_programs_never_panic(cut in 0usize..400, insert in "[ -~]{0,6}") {
        let base = include_str!("../../../../assets/examples/fixed_speed.tml");
        let at = base.char_indices().map(|(i, _)| i).nth(cut % base.chars().count()).unwrap_or(0);
        let text = format!("{}{insert}{}", &base[..at], &base[at..]);
        if let Ok(mut m) = machine(&text) {
            m.run_until(1000, |_| false);
        }
    }
}

// ---- Flow, the call stack, faults --------------------------------------------------------

#[test]
fn conditional_jumps_test_against_zero() {
    let m = run("int i; int n; i = 5;
loop: n += 1; i -= 1; GOTO loop, i, GT; END;");
    assert_eq!(var(&m, "n"), 5);
    let m = run("long x; int r; x = -1; CALL sub, x, LT; r += 10; END;
sub: r += 1; RET;");
    assert_eq!(var(&m, "r"), 11);
}

#[test]
fn the_stack_holds_eleven_calls_and_faults_on_the_twelfth() {
    let m = run("int depth;\nsub: depth += 1; CALL sub;");
    assert_eq!(m.run_state(), RunState::Faulted);
    let fault = m.fault().unwrap();
    assert_eq!(fault.kind, "stack_overflow");
    assert_eq!(fault.line, 2);
    assert_eq!(m.stack.len(), 11);
    assert_eq!(
        var(&m, "depth"),
        12,
        "the 12th CALL faults after its depth += 1"
    );
    assert_eq!(m.data[d::MER as usize] & (1 << 14), 1 << 14);
    assert_eq!(m.data[d::DER as usize] & 1, 1);
    // 12 increments + 11 CALLs completed: 23 statements, the fault in the 3rd tick (24th
    // statement), which is completed and counted.
    assert_eq!(m.steps(), 23);
    assert_eq!(m.ticks(), 3);
    let m = run("int x;\nx = 1;\nRET;\nx = 2;");
    assert_eq!(m.fault().unwrap().kind, "stack_underflow");
    assert_eq!(m.fault().unwrap().line, 3);
    assert_eq!(var(&m, "x"), 1);
    assert_eq!(m.data[d::DER as usize] & 2, 2);
}

#[test]
fn ten_statements_per_tick_and_the_end() {
    let src: String = (0..25).map(|_| "i += 1; ").collect();
    let mut m = machine(&format!("int i; {src}")).unwrap();
    m.step_tick();
    assert_eq!(m.pos(), Pos { tick: 1, step: 0 });
    assert_eq!(m.steps(), 10);
    m.step_command(10);
    assert_eq!(m.pos(), Pos { tick: 1, step: 1 });
    m.run_until(100, |_| false);
    assert_eq!(m.run_state(), RunState::Ended);
    assert_eq!((m.ticks(), m.steps()), (3, 25));
    let m = run("");
    assert_eq!(
        (m.ticks(), m.steps(), m.run_state()),
        (0, 0, RunState::Ended)
    );
    // Running past the last statement as the 10th ends in that tick.
    let src: String = (0..10).map(|_| "i += 1; ").collect();
    let m = run(&format!("int i; {src}"));
    assert_eq!((m.ticks(), m.steps()), (1, 10));
}

// ---- Events and WAIT! --------------------------------------------------------------------

#[test]
fn rt_wait_completes_a_hundred_ticks_later() {
    let m = run("long t; !RT 100; WAIT!; t = ATIME;");
    assert_eq!(
        var(&m, "t"),
        100,
        "set in tick 0, WAIT! completes in tick 100"
    );
    let m = run("long t; !MC; WAIT!; t = ATIME;");
    assert_eq!(
        var(&m, "t"),
        1,
        "at rest: the event is first checked at the end of tick 0"
    );
    let m = run("long t; WAIT!; t = ATIME;");
    assert_eq!(var(&m, "t"), 0, "no event ever set: at once");
}

#[test]
fn a_timed_wait_gives_up_and_srl_tells_why() {
    let mut m = machine("long t; int s; !IN#3 1; WAIT! 5; t = ATIME; s = SRL;").unwrap();
    m.run_until(100, |_| false);
    assert_eq!(var(&m, "t"), 5);
    assert_eq!(var(&m, "s") & (1 << 14), 0, "timed out: event bit clear");
    // With the input high from tick 2 it completes in tick 3.
    let mut m = machine("long t; int s; !IN#3 1; WAIT! 5; t = ATIME; s = SRL;").unwrap();
    m.run_until(2, |_| false);
    assert_eq!(
        m.run_state(),
        RunState::Waiting(servoscope_core::machine::WaitReason::Condition)
    );
    let loc = m.find("IN#3").unwrap();
    m.write(loc, 1).unwrap();
    m.run_until(100, |_| false);
    assert_eq!(var(&m, "t"), 3);
    assert_ne!(var(&m, "s") & (1 << 14), 0);
}

// ---- Motion ------------------------------------------------------------------------------

#[test]
fn the_vendor_profile_lands_exactly_speed_by_speed() {
    let mut m =
        machine("MODE PP; CSPD = 18.; CACC = 4; CPA; CPOS = 258; UPD; !MC; WAIT!; END;").unwrap();
    let mut speeds = Vec::new();
    while m.run_state().is_live() {
        m.step_tick();
        speeds.push(i64::from(m.data[d::TSPD as usize] as i32) as f64 / 65536.0);
    }
    let moving: Vec<f64> = speeds.iter().copied().skip_while(|&s| s == 0.0).collect();
    let mut expected = vec![4.0, 8.0, 12.0, 16.0];
    expected.extend([18.0; 10]);
    expected.extend([15.5, 11.5, 7.5, 3.5, 0.0]);
    assert_eq!(&moving[..expected.len()], &expected[..]);
    assert_eq!(m.data[d::TPOS as usize] as i32, 258);
    // APOS closes half the error each tick and settles exactly.
    let mut settle =
        machine("MODE PP; CSPD = 18.; CACC = 4; CPA; CPOS = 258; UPD; !RT 40; WAIT!; END;")
            .unwrap();
    settle.run_until(1000, |_| false);
    assert_eq!(settle.data[d::APOS as usize] as i32, 258);
    assert_eq!(settle.data[d::POSERR as usize], 0);
}

#[test]
fn stop_sap_and_retarget() {
    // STOP: decelerate at CACC from the slew speed: 8 → 6 → 4 → 2 → 0.
    let mut m = machine("MODE PP; CSPD = 8.; CACC = 2; CPA; CPOS = 100000; UPD; !RT 10; WAIT!; STOP; !MC; WAIT!; END;").unwrap();
    m.run_until(1000, |_| false);
    assert_eq!(m.run_state(), RunState::Ended);
    // 2+4+6+8×7 = 68 in ten ticks (UPD's tick included), then 6+4+2 = 12 more: 80.
    assert_eq!(m.data[d::TPOS as usize] as i32, 80);
    // SAP shifts APOS and the reference without moving; a moving profile's end follows.
    let m = run("SAP 1000; long a; a = APOS;");
    assert_eq!(var(&m, "a"), 1000);
    assert_eq!(m.data[d::TPOS as usize] as i32, 1000);
    let m = run("MODE PP; CSPD = 5.; CACC = 1; CPA; CPOS = 200; UPD; SAP 50; !MC; WAIT!; END;");
    assert_eq!(m.profile.end, 250, "the end moved with SAP");
    assert_eq!(m.data[d::TPOS as usize] as i32, 250);
    // Retarget during a move: a new UPD with TUM1 goes on from the reference.
    let m = run(
        "MODE PP; CSPD = 10.; CACC = 1; CPA; CPOS = 1000; UPD; !RT 20; WAIT!; TUM1; CPOS = 300; UPD; !MC; WAIT!; END;",
    );
    assert_eq!(m.data[d::TPOS as usize] as i32, 300);
    assert_eq!(m.profile.v, 0);
}

#[test]
fn upd_without_mode_or_with_bad_parameters_is_ignored() {
    let m = run("CSPD = 1.; CACC = 1.; CPOS = 10; UPD;");
    assert_eq!(m.data[d::MER as usize] & (1 << 14), 1 << 14);
    assert_eq!(m.data[d::DER as usize] & (1 << 4), 1 << 4);
    assert!(!m.profile.active);
    assert_eq!(m.run_state(), RunState::Ended, "not a fault");
    let m = run("MODE PP; CSPD = 0; CACC = 1.; UPD;");
    assert_eq!(m.data[d::DER as usize] & (1 << 4), 1 << 4);
    let m = run("MODE PP; AXISOFF; CSPD = 1.; CACC = 1.; UPD;");
    assert_eq!(m.data[d::DER as usize] & (1 << 4), 1 << 4);
}

// ---- The assembler -----------------------------------------------------------------------

#[test]
fn every_error_with_line_and_column() {
    let src = "int a;\nlong b;\na = b;\n  lbl: a = 1;\nGOTOO x;\nfixed f; a = 1.5;\nPROD = 3;\nb /= 4;\nSRB b, 1, 2;\na << 16;\nHOMING;\nc += 1;\na = 1\nMODE SP;\n!CAP;";
    let e = errors(src);
    let expect = [
        "3:5: error: 16/32-bit width mismatch",
        "4:3: error: label 'lbl' must start in column 1",
        "5:1: error: unknown instruction 'GOTOO' (did you mean 'GOTO'?)",
        "6:14: error: a fixed literal needs a fixed destination",
        "7:1: error: PROD is read-only",
        "8:6: error: the divisor must be a 16-bit datum, not an immediate",
        "9:5: error: SRB works on 16-bit data",
        "10:6: error: shift count outside 0..15",
        "11:1: error: the TML instruction HOMING is not supported by servoscope yet",
        "12:1: error: undeclared variable 'c'",
        "13:6: error: expected ';'",
        "14:6: error: MODE SP is not supported by servoscope yet",
        "15:2: error: the event !CAP is not supported by servoscope yet",
    ];
    assert_eq!(e.len(), expect.len(), "{e:#?}");
    for (got, want) in e.iter().zip(expect) {
        assert!(got.starts_with(want), "{got} should start with {want}");
    }
}

#[test]
fn names_labels_and_declarations() {
    assert!(errors("int a; int A;")[0].contains("duplicate variable 'A'"));
    assert!(errors("int CPOS;")[0].contains("'CPOS' is a TML name"));
    assert!(errors("int wait;")[0].contains("is a TML name"));
    assert!(errors("x: END;\nx: END;")[0].contains("duplicate label 'x'"));
    assert!(errors("GOTO nowhere;")[0].contains("undefined label 'nowhere'"));
    assert!(
        errors("a = 1; int a;")[0].contains("undeclared variable 'a'"),
        "declared before use"
    );
    // `W16 = label` stores the label's address: `a = lbl;` takes 2 words from 0x4000.
    assert_eq!(var(&run("int a; a = lbl;\nlbl: END;"), "a"), 0x4002);
    assert!(errors("int a; a = .5;")[0].contains("1:12"));
    assert!(errors("int aa; ab = 1;")[0].contains("did you mean 'aa'?"));
    // Case-insensitive names, several statements per line, comments, ';;'.
    let m = run("int Count; // a counter\ncount += 2;; COUNT += 3; cpos = 5;");
    assert_eq!(var(&m, "Count"), 5);
    assert_eq!(m.data[d::CPOS as usize], 5);
    // A label at the end marks the end.
    let m = run("int a; GOTO done; a = 1;\ndone:");
    assert_eq!(var(&m, "a"), 0);
    assert_eq!(m.run_state(), RunState::Ended);
}

#[test]
fn bad_characters_give_one_error_per_line() {
    let e = errors("int a; a = 1 $ 2 $;\nint b; b = 2 @;");
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(e[0].starts_with("1:14: error: unexpected character '$'"));
}

// ---- The examples, and the runner through the binary ------------------------------------

#[test]
fn the_examples_end_as_their_comments_say() {
    let m = run(include_str!("../../../../assets/examples/fixed_speed.tml"));
    assert_eq!(
        var(&m, "speed"),
        1_747_626,
        "26.666656494140625 counts/ms, truncated"
    );
    assert_eq!(
        servoscope_core::machine::value::q16_exact(var(&m, "speed")),
        "26.666656494140625"
    );
    // The issue's reading of the literal 26.6667: raw 1747629.
    assert_eq!(
        servoscope_core::machine::value::q16_exact(1_747_629),
        "26.6667022705078125"
    );
    assert_eq!(var(&m, "accel"), 1_747_626 / 150);
    assert_eq!(var(&m, "cpm"), 266);
    assert_eq!(m.preg_signed(), 17_476_260);
    let m = run(include_str!("../../../../assets/examples/shifts.tml"));
    assert_eq!(var(&m, "i"), -32766);
    assert_eq!(var(&m, "k"), 0x3456);
    assert_eq!(var(&m, "l"), -3);
    assert_eq!(m.preg_signed(), -3000);
    let m = run(include_str!("../../../../assets/examples/moves.tml"));
    assert_eq!(var(&m, "target"), 58, "258 − 200 from the reference (TUM1)");
    assert_eq!(m.profile.end, 58);
    let m = run(include_str!("../../../../assets/examples/wait_input.tml"));
    assert_eq!(var(&m, "found"), 0, "timed out");
    assert_eq!(m.ticks(), 501);
}

#[test]
fn hostile_literals_and_names_give_errors_not_panics() {
    // A fixed literal far past i128 on the way to its raw value.
    let e = errors("fixed f; f = 999999999999.9999999999999999999999999;");
    assert!(e[0].contains("out of range"), "{e:?}");
    // A variable called like an input is the variable; IN#5 is still the input.
    let m = run("int in5; in5 = 7;");
    let loc = m.find("in5").unwrap();
    assert_eq!(m.read(loc), 7);
    assert_ne!(m.find("IN#5"), Some(loc));
}

#[test]
fn a_fixed_literal_without_its_leading_zero_says_how_to_write_it() {
    let e = errors("CACC = .5;\nEND;");
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(e[0].starts_with("1:8: error: write 0.5"), "{e:?}");
    let e = errors("fixed f;\nf = -.25;\nEND;");
    assert!(e[0].contains("write 0.25"), "{e:?}");
}

/// Issue #22 (second look): a missing value is reported where it is missing, just past the
/// '=', not at the variable.
#[test]
fn a_missing_value_points_past_the_equals_sign() {
    let e = errors("int a;\na = ;\n");
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].starts_with("2:4: error: expected a value after '='"),
        "{e:?}"
    );
}

// ---- Literals with suffixes (spec §1.3) ------------------------------------------------------

#[test]
fn a_suffix_never_changes_the_value() {
    // EasyMotion writes long constants as `115343L`.
    let m = run(
        "long l; long u; int i; int j;\nl = 115343L;\nu = 4294967295UL;\ni = 65535U;\nj = 0x1FU;\nl += 2lu;\nEND;\n",
    );
    assert_eq!(var(&m, "l"), 115_345);
    assert_eq!(var(&m, "u"), -1, "4294967295 stored as its low 32 bits");
    assert_eq!(
        var(&m, "i"),
        -1,
        "65535 stored as its low 16 bits, read signed"
    );
    assert_eq!(var(&m, "j"), 31);
    let m = run("long l;\nSAP 100000L;\nl = APOS;\nEND;\n");
    assert_eq!(var(&m, "l"), 100_000, "SAP takes L");
}

#[test]
fn a_suffix_where_the_table_refuses_it_is_an_error_at_the_number() {
    let e = |src: &str| errors(&format!("int i; long l; fixed f;\n{src}\nEND;\n"));
    assert_eq!(
        e("i = 5L;"),
        ["2:5: error: misplaced suffix 'L': L marks a 32-bit integer, and this is 16-bit"]
    );
    assert_eq!(e("i = 70000U;"), ["2:5: error: a U number is 0..65535"]);
    assert_eq!(e("l = -5U;"), ["2:5: error: a U number is 0..65535"]);
    assert_eq!(
        e("f = 1U;"),
        ["2:5: error: misplaced suffix 'U': fixed data takes a fixed literal or a whole number"]
    );
    assert_eq!(
        e("i <<= 3U;"),
        ["2:7: error: misplaced suffix 'U': this number takes no suffix"]
    );
    assert_eq!(
        e("WAIT! 100L;"),
        ["2:7: error: misplaced suffix 'L': this number takes no suffix"]
    );
    assert_eq!(e("i = 5LL;"), ["2:5: error: malformed number '5LL'"]);
    assert_eq!(e("f = 1.5L;"), ["2:5: error: malformed number '1.5L'"]);
    assert!(e("l = 5L; l = 4294967295LU; i = 65535u;").is_empty());
}

#[test]
fn tml_data_servoscope_does_not_model_is_named_with_its_type_and_address() {
    // Spec §2.3.
    assert_eq!(
        errors("long l;\nl = CDEC;\nEND;\n"),
        ["2:5: error: 'CDEC' (fixed, 0x0858) is a TML datum that servoscope does not model yet"]
    );
    assert_eq!(
        errors("HOMEPOS = 5;\nEND;\n"),
        ["1:1: error: 'HOMEPOS' (long, 0x0992) is a TML datum that servoscope does not model yet"]
    );
    // Reserved: not a variable name either.
    assert!(!errors("int tjerk;\nEND;\n").is_empty());
    // Spec §5.10: the interrupt instructions.
    assert_eq!(
        errors("EINT;\nEND;\n"),
        ["1:1: error: EINT: servoscope does not model TML interrupts yet"]
    );
}

#[test]
fn a_multi_axis_statement_is_one_error_naming_it() {
    // Spec §5.10: it runs to the end of its `{…}` group (the `;` inside do not end it).
    assert_eq!(
        errors("[G1]{CPOS=2000;}; int x; x = 5;\nEND;\n"),
        [
            "1:1: error: multi-axis statement '[G1] {…}' (sent to group 1) is not supported by servoscope yet"
        ]
    );
    assert_eq!(
        errors("int x; int y;\n[3] x = y;\nEND;\n"),
        [
            "2:1: error: multi-axis statement '[3] x = y' (sent to axis 3) is not supported by servoscope yet"
        ]
    );
    assert_eq!(
        errors("  [B]{STOP; UPD;};\nEND;\n"),
        [
            "1:3: error: multi-axis statement '[B] {…}' (broadcast to every axis) is not supported by servoscope yet"
        ]
    );
    assert_eq!(
        errors("{CPOS = 5;};\nEND;\n"),
        ["1:1: error: multi-axis statement '{…}' is not supported by servoscope yet"]
    );
}

#[test]
fn real_tml_outside_the_subset_is_named_precisely() {
    // Spec §5.10.
    let first = |src: &str| errors(&format!("int a; int b;\n{src}\nEND;\n")).remove(0);
    assert_eq!(
        first("a = (b),dm;"),
        "2:5: error: addressing through a variable ((var),dm) is not supported by servoscope yet"
    );
    assert_eq!(
        first("a = b,dm;"),
        "2:5: error: addressing through a variable (X,dm) is not supported by servoscope yet"
    );
    assert_eq!(
        first("@ 0x4000;"),
        "2:1: error: a data word '@ …' (EasyMotion's homing and function tables) is not supported by servoscope yet"
    );
    assert_eq!(
        first("a = IN(3);"),
        "2:5: error: reading inputs with IN(…) is not supported by servoscope yet"
    );
    assert_eq!(
        first("UPD!;"),
        "2:1: error: UPD! is not supported by servoscope yet"
    );
    assert_eq!(
        first("MODE SP;"),
        "2:6: error: MODE SP is not supported by servoscope yet"
    );
}

#[test]
fn apos_and_aspd_answer_to_all_their_aliases() {
    // Spec §2.1: APOS (aliases APOS_LD, APOS_MT), ASPD (aliases ASPD_MT, ASPD_LD).
    let m = run(
        "long a; long b; fixed c; fixed e;\nSAP 1234;\na = APOS_MT;\nb = apos_ld;\nc = ASPD_LD;\ne = ASPD_MT;\nEND;\n",
    );
    assert_eq!(var(&m, "a"), 1234);
    assert_eq!(var(&m, "b"), 1234);
    assert_eq!(m.find("APOS_MT"), m.find("APOS"));
    assert_eq!(m.find("aspd_ld"), m.find("ASPD"));
    assert!(
        !errors("int apos_mt;\nEND;\n").is_empty(),
        "a TML name, not a variable"
    );
}
