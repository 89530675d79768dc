//! Every worked example of the vendor text (`shared/seeds/silverlode-calc.txt`) as a golden test.
//! Inputs and results come from the text; where spec §7 decided otherwise the test says so.

use crate::common;
use common::{reg, run_ok, ureg};

// ---- CLC -------------------------------------------------------------------------------------

#[test]
fn clc_abs() {
    let m = run_ok("WRP 11, -64\nCLC ABS, 11");
    assert_eq!(reg(&m, 11), 64);
}

#[test]
fn clc_add_example_1() {
    let m = run_ok("WRP 10, 0\nWRP 11, 25\nCLC ADD, 11");
    assert_eq!(reg(&m, 10), 25);
}

#[test]
fn clc_add_example_2_sums_two_registers() {
    // User[27] = User[25] + User[26] with User[26] = 10 (User[25] is not given; 32 here).
    let m = run_ok("WRP 25, 32\nWRP 26, 10\nCLC COPY, 25\nCLC ADD, 26\nCLC SAVE, 27");
    assert_eq!(reg(&m, 27), 42);
}

#[test]
fn clc_add_hi() {
    let m = run_ok("WRP 10, 0x100\nWRP 11, 0x00010000\nCLC ADD_HI, 11");
    assert_eq!(reg(&m, 10), 257);
}

#[test]
fn clc_add_lo() {
    let m = run_ok("WRP 10, 1\nWRP 11, 0x10000001\nCLC ADD_LO, 11");
    assert_eq!(reg(&m, 10), 2);
}

#[test]
fn clc_and() {
    let m = run_ok("WRP 11, 0x2BCD\nWRP 10, 0x5CBA\nCLC AND, 11");
    assert_eq!(reg(&m, 10), 0x0888);
}

#[test]
fn clc_clear() {
    let m = run_ok("WRP 11, 68\nCLC CLEAR, 11");
    assert_eq!(reg(&m, 11), 0);
}

#[test]
fn clc_copy() {
    let m = run_ok("WRP 27, 1234\nCLC COPY, 27");
    assert_eq!(reg(&m, 10), 1234);
}

#[test]
fn clc_copy_ref() {
    let m = run_ok("WRP 27, 100\nWRP 11, 27\nCLC COPY_REF, 11");
    assert_eq!(reg(&m, 10), 100);
}

#[test]
fn clc_save_ref() {
    let m = run_ok("WRP 10, 100\nWRP 27, 0\nWRP 11, 27\nCLC SAVE_REF, 11");
    assert_eq!(reg(&m, 27), 100);
}

#[test]
fn clc_copy_word_hi_acc() {
    let m = run_ok("WRP 10, 0\nWRP 11, 0xD3\nCLC COPY_WORD_HI_ACC, 11");
    assert_eq!(ureg(&m, 10), 0x00D3_0000);
}

#[test]
fn clc_copy_word_hi_reg() {
    let m = run_ok("WRP 11, 0\nWRP 10, 0xC8D3\nCLC COPY_WORD_HI_REG, 11");
    assert_eq!(ureg(&m, 11), 0xC8D3_0000);
}

#[test]
fn clc_copy_word_lo_reg() {
    let m = run_ok("WRP 11, 0\nWRP 10, 0xC8D3\nCLC COPY_WORD_LO_REG, 11");
    assert_eq!(ureg(&m, 11), 0xC8D3);
}

#[test]
fn clc_sign_extend_hi() {
    let m = run_ok("WRP 11, 0xABCD893F\nWRP 10, 0\nCLC SEXT_HI, 11");
    assert_eq!(ureg(&m, 10), 0xFFFF_ABCD);
}

#[test]
fn clc_sign_extend_lo() {
    let m = run_ok("WRP 11, 0xABCD893F\nWRP 10, 0\nCLC SEXT_LO, 11");
    assert_eq!(ureg(&m, 10), 0xFFFF_893F);
}

#[test]
fn clc_dec_and_inc() {
    let m = run_ok("WRP 11, 100\nCLC DEC, 11\nWRP 12, 100\nCLC INC, 12");
    assert_eq!(reg(&m, 11), 99);
    assert_eq!(reg(&m, 12), 101);
}

#[test]
fn clc_div() {
    let m = run_ok("WRP 10, 100\nWRP 11, 10\nCLC DIV, 11");
    assert_eq!(reg(&m, 10), 10);
}

#[test]
fn clc_max_and_min() {
    let m = run_ok("WRP 10, 50\nWRP 11, 10\nCLC MAX, 11\nCLC SAVE, 20\nWRP 10, 50\nCLC MIN, 11");
    assert_eq!(reg(&m, 20), 50);
    assert_eq!(reg(&m, 10), 10);
}

#[test]
fn clc_mod() {
    let m = run_ok("WRP 10, 33\nWRP 11, 10\nCLC MOD, 11");
    assert_eq!(reg(&m, 10), 3);
}

#[test]
fn clc_mult_signed_and_unsigned() {
    let m = run_ok(
        "WRP 10, 5\nWRP 11, -10\nCLC MULT_S, 11\nCLC SAVE, 20\nWRP 10, 5\nWRP 11, 10\nCLC MULT_U, 11",
    );
    assert_eq!(reg(&m, 20), -50);
    assert_eq!(reg(&m, 10), 50);
}

#[test]
fn clc_neg() {
    let m = run_ok("WRP 11, 100\nCLC NEG, 11");
    assert_eq!(reg(&m, 11), -100);
}

#[test]
fn clc_or() {
    let m = run_ok("WRP 11, 0x8BCD\nWRP 10, 0xDCBA\nCLC OR, 11");
    assert_eq!(ureg(&m, 10), 0xDFFF);
}

#[test]
fn clc_shifts() {
    let m = run_ok(
        "WRP 11, 0x24ADD6D5\nCLC SHL, 11\nWRP 12, 0xA4ADD6D5\nCLC SHR_S, 12\nWRP 13, 0xA4ADD6D5\nCLC SHR_U, 13",
    );
    assert_eq!(ureg(&m, 11), 0x495B_ADAA);
    assert_eq!(ureg(&m, 12), 0xD256_EB6A);
    assert_eq!(ureg(&m, 13), 0x5256_EB6A);
}

#[test]
fn clc_sub_example_1() {
    let m = run_ok("WRP 10, 10\nWRP 11, 25\nCLC SUB, 11");
    assert_eq!(reg(&m, 10), -15);
}

#[test]
fn clc_sub_example_2_follows_the_spec_not_the_typo() {
    // The vendor's Sub "Example 2" uses Add (spec §7: a typo); the intended R27 = R25 - R26.
    let m = run_ok("WRP 25, 32\nWRP 26, 10\nCLC COPY, 25\nCLC SUB, 26\nCLC SAVE, 27");
    assert_eq!(reg(&m, 27), 22);
}

#[test]
fn clc_sub_rev() {
    let m = run_ok("WRP 10, 10\nWRP 11, 25\nCLC SUB_REV, 11");
    assert_eq!(reg(&m, 10), 15);
}

#[test]
fn clc_sub_target_moves_the_zero_point() {
    let m = run_ok("WRP 0, 4510\nWRP 1, 4500\nWRP 4, 4400\nCLC SUB_TARGET, 4");
    assert_eq!(reg(&m, 0), 110);
    assert_eq!(reg(&m, 1), 100);
}

#[test]
fn clc_xor() {
    let m = run_ok("WRP 11, 0x04018BCD\nWRP 10, 0x0002DCBA\nCLC XOR, 11");
    assert_eq!(ureg(&m, 10), 0x0403_5777);
}

// ---- CLD / CLX (User[25] = result, User[26] = reg1) ------------------------------------------

#[test]
fn cld_abs() {
    let m = run_ok("WRP 26, -64\nCLD ABS, 25, 26, 0");
    assert_eq!(reg(&m, 25), 64);
}

#[test]
fn cld_add() {
    let m = run_ok("WRP 26, 10\nCLD ADD, 25, 26, 25");
    assert_eq!(reg(&m, 25), 35);
}

#[test]
fn cld_add_hi_and_lo() {
    let m = run_ok(
        "WRP 26, 0x000A0000\nCLD ADD_HI, 25, 26, 0x4C\nWRP 27, 0x0200000A\nCLD ADD_LO, 28, 27, 0x4C",
    );
    assert_eq!(reg(&m, 25), 0x56);
    assert_eq!(reg(&m, 28), 0x56);
}

#[test]
fn cld_and() {
    let m = run_ok("WRP 26, 0x0100ABCD\nCLD AND, 25, 26, 0x0100DCBA");
    assert_eq!(ureg(&m, 25), 0x0100_8888);
}

#[test]
fn cld_copy() {
    let m = run_ok("WRP 26, -77\nCLD COPY, 25, 26, 0");
    assert_eq!(reg(&m, 25), -77);
}

#[test]
fn cld_sign_extend_hi_follows_spec() {
    // The vendor shows 0x0000ABCD; spec §7 decides SEXT_HI sign-extends like its CLC twin.
    let m = run_ok("WRP 26, 0xABCD0003\nCLD SEXT_HI, 25, 26, 0");
    assert_eq!(ureg(&m, 25), 0xFFFF_ABCD);
}

#[test]
fn cld_sign_extend_lo_follows_spec() {
    // The vendor shows 0xABCD; spec §5.2 defines SEXT_LO as sx16(LO(R[reg1])) = 0xFFFFABCD.
    let m = run_ok("WRP 26, 0x0003ABCD\nCLD SEXT_LO, 25, 26, 0");
    assert_eq!(ureg(&m, 25), 0xFFFF_ABCD);
}

#[test]
fn cld_pack_words() {
    let m = run_ok(
        "WRP 26, 0x0100C800\nCLD PACK_LO_LO, 25, 26, 0xD3\n\
         WRP 27, 0xC8000008\nCLD PACK_HI_LO, 28, 27, 0xD3\n\
         WRP 29, 0xC8000000\nCLD PACK_HI_HI, 30, 29, 0x00D30000",
    );
    assert_eq!(ureg(&m, 25), 0xC800_00D3);
    assert_eq!(ureg(&m, 28), 0xC800_00D3);
    assert_eq!(ureg(&m, 30), 0xC800_00D3);
}

#[test]
fn cld_div() {
    let m = run_ok("WRP 26, 100\nCLD DIV, 25, 26, 10");
    assert_eq!(reg(&m, 25), 10);
}

#[test]
fn cld_div_rev_follows_spec_not_the_typo() {
    // The vendor's example (100 / LO(100) = 10) is a typo per spec §7: 100 / 100 = 1.
    let m = run_ok("WRP 26, 100\nCLD DIV_REV, 25, 26, 100");
    assert_eq!(reg(&m, 25), 1);
}

#[test]
fn cld_div_u64() {
    // 100,000,000,000,000 = 0x5AF3_107A_4000 in R26:R27.
    let m = run_ok("WRP 26, 0x5AF3\nWRP 27, 0x107A4000\nCLD DIV_U64, 25, 26, 100_000_000");
    assert_eq!(reg(&m, 25), 1_000_000);
}

#[test]
fn cld_max_and_min() {
    let m = run_ok("WRP 26, 50\nCLD MAX, 25, 26, 10\nCLD MIN, 24, 26, 10");
    assert_eq!(reg(&m, 25), 50);
    assert_eq!(reg(&m, 24), 10);
}

#[test]
fn cld_mod_rev() {
    let m = run_ok("WRP 26, 15\nCLD MOD_REV, 25, 26, 100");
    assert_eq!(reg(&m, 25), 10);
}

#[test]
fn cld_mod() {
    let m = run_ok("WRP 26, 100\nCLD MOD, 25, 26, 15");
    assert_eq!(reg(&m, 25), 10);
}

#[test]
fn cld_mult_unsigned_and_signed() {
    let m = run_ok("WRP 26, 5\nCLD MULT_U, 25, 26, 10\nWRP 27, -5\nCLD MULT_S, 28, 27, 10");
    assert_eq!(reg(&m, 25), 50);
    assert_eq!(reg(&m, 28), -50);
}

#[test]
fn cld_mult_s64_shr16_scales_by_254_3467() {
    let m = run_ok("WRP 26, 1000\nCLD MULT_S64_SHR16, 25, 26, q16(254.3467)");
    assert_eq!(reg(&m, 25), 254346);
    // The literal the vendor computed by hand.
    let m = run_ok("WRP 26, 1000\nCLD MULT_S64_SHR16, 25, 26, 16668865");
    assert_eq!(reg(&m, 25), 254346);
}

#[test]
fn cld_mult_u64() {
    let m = run_ok("WRP 26, 1_000_000\nCLD MULT_U64, 28, 26, 1_000_000_000");
    let product = (u64::from(ureg(&m, 28)) << 32) | u64::from(ureg(&m, 29));
    assert_eq!(product, 1_000_000_000_000_000);
}

#[test]
fn cld_neg() {
    let m = run_ok("WRP 26, 100\nCLD NEG, 25, 26, 0");
    assert_eq!(reg(&m, 25), -100);
}

#[test]
fn cld_or() {
    let m = run_ok("WRP 26, 0x03008BCD\nCLD OR, 25, 26, 0x0001DCBA");
    assert_eq!(ureg(&m, 25), 0x0301_DFFF);
}

#[test]
fn cld_sub_and_sub_rev() {
    let m = run_ok("WRP 26, 25\nCLD SUB, 25, 26, 10\nCLD SUB_REV, 24, 26, 10");
    assert_eq!(reg(&m, 25), 15);
    assert_eq!(reg(&m, 24), -15);
}

#[test]
fn cld_xor() {
    let m = run_ok("WRP 26, 0x03008BCD\nCLD XOR, 25, 26, 0x0100DCBA");
    assert_eq!(ureg(&m, 25), 0x0200_5777);
}

#[test]
fn clx_takes_data_from_a_register() {
    let m = run_ok("WRP 26, 1000\nWRP 27, 16668865\nCLX MULT_S64_SHR16, 25, 26, 27");
    assert_eq!(reg(&m, 25), 254346);
}

#[test]
fn clx_reads_reg2_before_writing_the_result() {
    // res == reg2: d must be the old value.
    let m = run_ok("WRP 26, 7\nWRP 25, 5\nCLX ADD, 25, 26, 25");
    assert_eq!(reg(&m, 25), 12);
}

// ---- Queues (vendor examples; base R27) --------------------------------------------------------

#[test]
fn queue_init_reports_its_size() {
    let m = run_ok("CLD Q_INIT, 10, 27, 2");
    assert_eq!(reg(&m, 10), 2);
    assert_eq!(ureg(&m, 27), 2 << 16);
    assert_eq!(reg(&m, 28), 0);
}

#[test]
fn queue_push_head_returns_remaining_space() {
    // Size 3: push 10, 20, 30 leaves 2, 1, 0 free; the head wraps back to slot 0 (R29).
    let m = run_ok(
        "CLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD_ERR, 40, 27, 10\nCLD Q_PUSH_HEAD_ERR, 41, 27, 20\nCLD Q_PUSH_HEAD_ERR, 42, 27, 30",
    );
    assert_eq!((reg(&m, 40), reg(&m, 41), reg(&m, 42)), (2, 1, 0));
    assert_eq!((reg(&m, 29), reg(&m, 30), reg(&m, 31)), (10, 20, 30));
    assert_eq!(ureg(&m, 28), 0, "head and tail both at slot 0");
    assert_eq!(ureg(&m, 27), 3 << 16 | 3);
}

#[test]
fn queue_pop_head_takes_the_newest() {
    let m = run_ok(
        "CLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD, 10, 27, 1\nCLD Q_PUSH_HEAD, 10, 27, 2\nCLD Q_POP_HEAD_ERR, 33, 27, 0",
    );
    assert_eq!(reg(&m, 33), 2);
    assert_eq!(ureg(&m, 28) >> 16, 1, "head back on slot 1 (R30)");
}

#[test]
fn queue_push_tail_goes_below_the_tail() {
    // After pushing 1, 2 at the head, a tail push wraps to slot 2 (R31) and leaves 1 free.
    let m = run_ok(
        "CLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD, 10, 27, 1\nCLD Q_PUSH_HEAD, 10, 27, 2\nCLD Q_PUSH_TAIL_ERR, 33, 27, 100",
    );
    assert_eq!(reg(&m, 31), 100);
    assert_eq!(reg(&m, 33), 0);
    assert_eq!(ureg(&m, 28) & 0xFFFF, 2, "tail on slot 2");
}

#[test]
fn queue_pop_tail_takes_the_oldest() {
    let m = run_ok(
        "CLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD, 10, 27, 1\nCLD Q_PUSH_HEAD, 10, 27, 2\nCLD Q_PUSH_HEAD, 10, 27, 3\nCLD Q_POP_TAIL_ERR, 33, 27, 0",
    );
    assert_eq!(reg(&m, 33), 1);
    assert_eq!(ureg(&m, 28) & 0xFFFF, 1, "tail moved up to slot 1 (R30)");
}

#[test]
fn queue_read_element_from_both_ends() {
    // Queue 1 (tail), 2, 3 (head): element 0 is the newest (3), -1 the tail (1).
    let m = run_ok(
        "CLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD, 10, 27, 1\nCLD Q_PUSH_HEAD, 10, 27, 2\nCLD Q_PUSH_HEAD, 10, 27, 3\n\
         CLD Q_READ, 33, 27, 0\nCLD Q_READ, 34, 27, -1\nWRP 26, 1\nCLX Q_READ, 35, 27, 26",
    );
    assert_eq!(reg(&m, 33), 3);
    assert_eq!(reg(&m, 34), 1);
    assert_eq!(reg(&m, 35), 2);
    assert_eq!(ureg(&m, 27) & 0xFFFF, 3, "reading does not remove");
}
