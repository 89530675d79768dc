//! Programs more than one benchmark runs.

/// Eight commands a round: CLD, CLX and CLC arithmetic and a conditional jump.
pub const ARITHMETIC: &str = "\
loop: CLD ADD, 20, 20, 3
      CLX MULT_S, 21, 20, 22
      CLC ADD, 21
      CLD MULT_S64_SHR16, 23, 21, q16(1.5)
      CLX XOR, 24, 23, 20
      CLC INC, 25
      CLD AND, 26, 25, 0x7FFFFFFF
      JMP loop, !NEGATIVE
";
