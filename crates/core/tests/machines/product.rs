//! The Product panel's arithmetic (SilverLode, spec §5.1–§5.2): for the multiply or divide at the
//! program counter, the full product or quotient as bits, which bits the result keeps, what is
//! lost in words and the real-number line. Expected values are worked out by hand from the spec.

use crate::common;

use servoscope_core::machine::Machine;
use servoscope_core::machine::bits::Breakdown;
use servoscope_core::machine::bits::Keep;
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::arith::at_pc;

/// The breakdown of the command on `line` (1-based), run up to it.
fn at_line(source: &str, line: usize) -> Breakdown {
    let mut m: SilverLode = common::machine(source);
    m.run_until(1_000, |m| m.line_of(m.pc()) == Some(line));
    assert_eq!(m.line_of(m.pc()), Some(line), "stopped on line {line}");
    at_pc(&m).expect("an arithmetic command")
}

#[test]
fn the_fixed_point_lessons_multiply_keeps_bits_47_to_16_and_says_what_the_shift_dropped() {
    // q16(0.0254) = round(0.0254 × 65536) = round(1664.6144) = 1665.
    let b = at_line(
        "WRP 20, 40000\nCLD MULT_S64_SHR16, 21, 20, q16(0.0254)\nEND\n",
        2,
    );
    assert_eq!(b.line, 2);
    assert_eq!(b.command, "CLD MULT_S64_SHR16, R21, R20, 1665");
    let product = &b.rows[2];
    // 40000 × 1665 = 66 600 000 = 1016 × 65536 + 15424.
    assert_eq!(product.value, 66_600_000);
    assert_eq!(product.width, 64);
    assert_eq!(product.point, Some(16));
    assert_eq!(product.keep, Keep::Bits(47, 16));
    assert!(product.keep.keeps(16) && product.keep.keeps(47));
    assert!(!product.keep.keeps(15) && !product.keep.keeps(48));
    assert_eq!(b.rows[1].point, Some(16), "the factor is drawn as Q16.16");
    assert!(
        b.notes.iter().any(
            |n| n == "bits 15..0 = 15424 = 0.2354 dropped by the shift (toward minus infinity)"
        ),
        "{:?}",
        b.notes
    );
    assert!(
        b.notes.iter().any(|n| n.contains("no overflow")),
        "{:?}",
        b.notes
    );
    // 1665 / 65536 = 0.0254058837890625; 66 600 000 / 65536 = 1016.2353515625;
    // (1016 − 1016.2353515625) / 1016.2353515625 = −0.0232 %.
    assert_eq!(
        b.real.as_deref(),
        Some("40000 × 0.0254058837890625 = 1016.2353515625 exact; stored 1016; error −0.023 %")
    );
}

#[test]
fn a_q16_product_past_bit_47_is_called_an_overflow() {
    // 2147483647 × 2.0 (131072) = 2^48 − 2^17: bit 47 and up are not a sign extension.
    let b = at_line(
        "WRP 20, 2147483647\nCLD MULT_S64_SHR16, 21, 20, q16(2.0)\nEND\n",
        2,
    );
    assert!(
        b.notes
            .iter()
            .any(|n| n == "bits 63..48 are not a sign extension of bit 47: overflow"),
        "{:?}",
        b.notes
    );
}

#[test]
fn a_32_bit_multiply_keeps_the_low_word_and_names_the_overflow() {
    // 100000 × 100000 = 10^10 = 2 × 2^32 + 1410065408.
    let b = at_line("WRP 20, 100000\nCLD MULT_S, 21, 20, 100000\nEND\n", 2);
    assert_eq!(b.rows[2].value, 10_000_000_000);
    assert_eq!(b.rows[2].keep, Keep::Bits(31, 0));
    assert!(
        b.notes.iter().any(|n| n.contains("overflow")),
        "{:?}",
        b.notes
    );
    assert_eq!(
        b.real.as_deref(),
        Some("100000 × 100000 = 10000000000 exact; stored 1410065408 (wrapped)")
    );
    let fine = at_line("WRP 10, -7\nWRP 20, 6\nCLC MULT_S, 20\nEND\n", 3);
    assert_eq!(fine.real.as_deref(), Some("-7 × 6 = -42 exact; stored -42"));
    assert!(fine.notes.iter().any(|n| n.contains("nothing lost")));
}

#[test]
fn mult_u64_keeps_all_64_bits_in_two_registers() {
    // 4294967295 × 4294967295 = 18446744065119617025 = 0xFFFFFFFE_00000001.
    let b = at_line("WRP 20, -1\nCLD MULT_U64, 30, 20, -1\nEND\n", 2);
    assert_eq!(b.rows[2].value, 0xFFFF_FFFE_0000_0001);
    assert_eq!(b.rows[2].keep, Keep::Bits(63, 0));
    assert_eq!(
        b.notes,
        ["R30 gets bits 63..32 (4294967294), R31 bits 31..0 (1): nothing lost"]
    );
}

#[test]
fn a_divide_keeps_the_quotient_and_says_what_the_remainder_was() {
    // 100 / 7 = 14 remainder 2; 2/7 = 0.2857; (14 − 14.285714) / 14.285714 = −2 %.
    let b = at_line("WRP 20, 100\nCLD DIV, 21, 20, 7\nEND\n", 2);
    let (quotient, remainder) = (&b.rows[2], &b.rows[3]);
    assert_eq!(quotient.value, 14);
    assert_eq!(quotient.keep, Keep::Bits(31, 0));
    assert_eq!(remainder.value, 2);
    assert_eq!(remainder.keep, Keep::Nothing);
    assert!(
        b.notes
            .iter()
            .any(|n| n == "the remainder 2 is discarded: 0.2857 of a unit, truncated toward zero"),
        "{:?}",
        b.notes
    );
    assert_eq!(
        b.real.as_deref(),
        Some("100 ÷ 7 = 14.285714 exact; stored 14; error −2.000 %")
    );
    // MOD keeps the remainder; its sign follows the dividend: −100 % 7 = −2.
    let m = at_line("WRP 20, -100\nCLD MOD, 21, 20, 7\nEND\n", 2);
    assert_eq!(m.rows[2].keep, Keep::Nothing);
    assert_eq!(m.rows[3].keep, Keep::Bits(31, 0));
    assert_eq!(m.rows[3].value, u64::from((-2i32) as u32));
}

#[test]
fn only_the_low_16_bits_of_a_divisor_count_and_faults_are_announced() {
    // 0x10007: sx16(LO) = 7.
    let b = at_line("WRP 20, 100\nCLD DIV, 21, 20, 0x10007\nEND\n", 2);
    assert!(
        b.notes
            .iter()
            .any(|n| n == "only the low 16 bits of 65543 divide: sx16(LO) = 7")
    );
    let zero = at_line("WRP 20, 100\nCLD DIV, 21, 20, 0x10000\nEND\n", 2);
    assert!(
        zero.notes.iter().any(|n| n.contains("divide_by_zero")),
        "{:?}",
        zero.notes
    );
    assert_eq!(zero.real, None);
    let overflow = at_line("WRP 20, -2147483648\nCLD DIV, 21, 20, -1\nEND\n", 2);
    assert!(overflow.notes.iter().any(|n| n.contains("divide_overflow")));
    // DIV_U64: (1 : 0) = 2^32 ÷ 1 needs 33 bits.
    let wide = at_line("WRP 30, 1\nWRP 31, 0\nCLD DIV_U64, 21, 30, 1\nEND\n", 3);
    assert!(
        wide.notes.iter().any(|n| n.contains("divide_overflow")),
        "{:?}",
        wide.notes
    );
    let ok = at_line("WRP 30, 1\nWRP 31, 0\nCLD DIV_U64, 21, 30, 3\nEND\n", 3);
    // 4294967296 / 3 = 1431655765 remainder 1.
    assert_eq!(ok.rows[2].value, 1_431_655_765);
    assert!(ok.notes.iter().any(|n| n == "the remainder 1 is discarded"));
}

#[test]
fn other_commands_have_no_breakdown() {
    let mut m: SilverLode = common::machine("CLD ADD, 21, 20, 5\nEND\n");
    assert!(at_pc(&m).is_none());
    m.run_until(1_000, |_| false);
    assert!(at_pc(&m).is_none(), "past the end");
}

mod tml {
    use servoscope_core::machine::Machine;
    use servoscope_core::machine::bits::Keep;
    use servoscope_core::machine::tml::Tml;
    use servoscope_core::machine::tml::arith::{division_at_pc, last_multiply};
    use servoscope_core::machine::tml::dialect::machine;

    /// Run `src` until the statement on `line` is next.
    fn to_line(src: &str, line: usize) -> Tml {
        let mut m = machine(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
        m.run_until(10_000, |m| {
            m.program
                .stmts
                .get(m.pc as usize)
                .is_some_and(|s| s.line == line)
        });
        m
    }

    /// Issue #43 item 4: `<< n` moves the product's bits 47−n..0 up to 47..n.
    #[test]
    fn a_left_shift_names_the_bits_that_move() {
        let m = to_line("int v;\nv = 4694;\nv * 293 << 12;\nEND;\n", 4);
        let b = last_multiply(&m).expect("a multiply ran");
        assert!(
            b.notes
                .iter()
                .any(|n| n == "<< 12: bits 35..0 of the product move to 47..12; low bits are 0"),
            "{:?}",
            b.notes
        );
    }

    #[test]
    fn a_fixed_product_is_32_16_with_its_binary_point_and_real_line() {
        // §5.3: a fixed A makes a 32.16 product. 1.5 (98304) × 3 = 294912 = 4.5.
        let m = to_line("fixed f;\nint i;\nf = 1.5;\ni = 3;\nf * i;\nEND;\n", 6);
        let b = last_multiply(&m).expect("a multiply ran");
        assert_eq!(b.line, 5);
        assert_eq!(b.rows[0].value, 294_912);
        assert_eq!(b.rows[0].point, Some(16));
        assert_eq!(b.rows[0].keep, Keep::Bits(47, 0));
        assert_eq!(
            b.real.as_deref(),
            Some("1.5 × 3 << 0 = 4.5 exact; PREG holds 4.5; error 0 %")
        );
        // >> 4 drops the low 4 bits: 294912 has them 0.
        let m = to_line("fixed f;\nint i;\nf = 1.5;\ni = 3;\nf * i >> 4;\nEND;\n", 6);
        let b = last_multiply(&m).expect("a multiply ran");
        assert_eq!(b.rows[0].keep, Keep::Bits(51, 4));
        assert!(
            b.notes.iter().any(|n| n.contains("nothing lost")),
            "{:?}",
            b.notes
        );
    }

    /// A later `PROD << 15` changes PREG, not the multiply: the breakdown shows PREG as the
    /// multiply left it and calls nothing an overflow (it mixed the two: "-3 × 1000 = -3000
    /// exact; << 0 → PREG = -98304000 … the product overflowed").
    #[test]
    fn a_later_product_shift_is_not_the_multiplys_overflow() {
        let m = to_line("long l;\nl = -3;\nl * 1000 << 0;\nPROD << 15;\nEND;\n", 5);
        let b = last_multiply(&m).expect("a multiply ran");
        assert_eq!(
            b.real.as_deref(),
            Some("-3 × 1000 = -3000 exact; << 0 → PREG = -3000")
        );
        assert!(
            !b.notes.iter().any(|n| n.contains("overflowed")),
            "{:?}",
            b.notes
        );
        assert!(
            b.notes
                .iter()
                .any(|n| n
                    == "PREG was changed since (now -98304000): shown as this multiply left it"),
            "{:?}",
            b.notes
        );
    }

    #[test]
    fn an_int_product_has_no_binary_point() {
        let m = to_line("int a;\nint b;\na = -300;\nb = 7;\na * b;\nEND;\n", 6);
        let b = last_multiply(&m).expect("a multiply ran");
        assert_eq!(b.rows[0].point, None);
        assert_eq!(
            b.real.as_deref(),
            Some("-300 × 7 = -2100 exact; << 0 → PREG = -2100")
        );
    }

    #[test]
    fn a_division_shows_the_remainder_it_discards() {
        // §5.4: long 10 /= 4 → 163840 = 2.5 exactly (N = 655360, remainder 0).
        let m = to_line("long l;\nint d;\nl = 10;\nd = 4;\nl /= d;\nEND;\n", 5);
        let b = division_at_pc(&m).expect("the division is next");
        assert_eq!(b.rows[0].value, 655_360);
        assert_eq!(b.rows[1].value, 163_840);
        assert_eq!(b.rows[1].keep, Keep::Bits(31, 0));
        assert_eq!(b.rows[2].keep, Keep::Nothing);
        assert!(b.notes.iter().any(|n| n.contains("exact")), "{:?}", b.notes);
        // 1 /= 3: N = 65536; 65536 / 3 = 21845 remainder 1 (21845/65536 = 0.3333282…).
        let m = to_line("long l;\nint d;\nl = 1;\nd = 3;\nl /= d;\nEND;\n", 5);
        let b = division_at_pc(&m).expect("the division is next");
        assert_eq!(b.rows[1].value, 21_845);
        assert_eq!(b.rows[2].value, 1);
        assert!(
            b.notes
                .iter()
                .any(|n| n.starts_with("the remainder 1 is discarded: 0.3333")),
            "{:?}",
            b.notes
        );
    }
}
