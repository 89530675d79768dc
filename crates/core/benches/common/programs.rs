//! Programs more than one benchmark runs.
#![allow(dead_code)]

/// The vendor manual's idiom (CLC COPY/ADD/SAVE, a Q16.16 scaling, CLX XOR, CLC DEC, a
/// conditional jump) as a loop: seven commands a round.
pub const IDIOM: &str = include_str!("idiom.qsl");

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

/// A 100-instruction OpenNet scan: one condition, then 99 advanced instructions of every type,
/// a third of them with REP 4.
pub fn opennet_program() -> String {
    let mut src = String::from("LODN M0\n");
    let forms = [
        "ADD(W) D100(R) D0 D0 REP 4",
        "ADD(I) D1 7 D1",
        "SUB(L) D2 3 D2",
        "MUL(W) D10 D11 D20",
        "DIV(I) D1 5 D30",
        "MOV(D) D2(R) D40(R) REP 4",
        "ADD(D) D50 65537 D50",
        "INC(W) D60",
        "SUB(W) D100(R) D61 D62(R) REP 4",
    ];
    for i in 0..99 {
        src.push_str(forms[i % forms.len()]);
        src.push('\n');
    }
    src.push_str("END\n");
    src
}

/// A 100-instruction DL205 scan: rungs of loads, BCD and binary math and outs.
pub fn dl205_program() -> String {
    let mut src = String::from("STR SP0\nLD K1234\nOUT V0\nLDD K00125000\nOUTD V2\n");
    let rung = [
        "STR SP1", "LDD V2", "ADDD K1", "OUTD V2", "LD V0", "MUL K3", "DIV K7", "OUT V10", "POP",
        "OUT V11", "LDD V2", "LDD K400", "SUBS", "BIN", "ADDB K5", "OUTD V20", "LD V0", "SHFL K2",
        "OUT V30",
    ];
    let mut count = 5;
    'fill: loop {
        for i in rung {
            if count == 99 {
                break 'fill;
            }
            src.push_str(i);
            src.push('\n');
            count += 1;
        }
    }
    // The last rung needs an output before END.
    src.push_str("END\n");
    src
}

/// A 100-instruction DL205 program of what ladder programs are made of: 8 timers (TMR, TMRA),
/// 8 counters (CNT, UDC) with their legs, edge contacts and PD, contacts on the status bits,
/// two stages taking turns (one runs, one is skipped, each scan), a subroutine call and a
/// little BCD math on the current values.
pub fn dl205_ladder_program() -> String {
    let mut src = String::new();
    for n in 0..4 {
        src.push_str(&format!("STR SP1\nTMR T{n} K30\n"));
        src.push_str(&format!("STR SP4\nSTR X1\nTMRA T{} K50\n", 10 + 2 * n));
        src.push_str(&format!("STR SP5\nSTR X2\nCNT CT{n} K10\n"));
        src.push_str(&format!(
            "STR SP5\nSTR SP6\nSTR X3\nUDC CT{} K100\n",
            10 + 2 * n
        ));
    }
    for n in 0..4 {
        src.push_str(&format!("STR T{n}\nAND CT{n}\nOUT Y{n}\n"));
        src.push_str(&format!("STRPD T{n}\nORND CT{n}\nPD C{n}\n"));
    }
    src.push_str("STR SP1\nGTS K1\n");
    let math = [
        "STR SP1",
        "LD V0",
        "ADD V1",
        "OUT V2000",
        "LD V1000",
        "CMP K5",
        "STR SP61",
        "OUT C20",
    ];
    let stages =
        "ISG S0\nSTR SP1\nOUT C30\nSTR SP7\nJMP S1\nSG S1\nSTR SP1\nOUT C31\nSTRN SP7\nJMP S0\n";
    let subroutine = "SBR K1\nSTR SP1\nINCB V2100\nRT\n";
    // Math up to the stages, END, and the subroutine: 100 instructions.
    let fixed = stages.lines().count() + 1 + subroutine.lines().count();
    let mut count = src.lines().count();
    'fill: loop {
        for i in math {
            if count + fixed == 100 {
                break 'fill;
            }
            src.push_str(i);
            src.push('\n');
            count += 1;
        }
    }
    src.push_str(stages);
    src.push_str("END\n");
    src.push_str(subroutine);
    src
}

/// A 100-instruction OpenNet program of what ladder programs are made of: 8 timers of all
/// four kinds on clocks, 8 counters (CNT and CUD with their input blocks), a CMP over a
/// counter, an MCS area that the 1-s clock turns on and off, a jump, an edge and a little
/// arithmetic on the current values.
pub fn opennet_ladder_program() -> String {
    let mut src = String::new();
    for (n, timer) in ["TML", "TIM", "TMH", "TMS"].iter().enumerate() {
        src.push_str(&format!("LOD M8125\n{timer} T{n} 30\n"));
        src.push_str(&format!("LOD M8122\nTMH T{} 5\n", 4 + n));
    }
    src.push_str("LOD M8121\nMCS\n");
    for n in 0..4 {
        src.push_str(&format!("LODN T{n}\nLOD M8122\nCNT C{n} 10\n"));
        src.push_str(&format!(
            "LOD C{n}\nLOD M8123\nLOD I3\nCUD C{} 100\n",
            4 + n
        ));
    }
    src.push_str("MCR\n");
    src.push_str("LOD M8125\nCMP>=(W) C0 5 M20\n");
    for n in 0..4 {
        src.push_str(&format!("LOD T{n}\nAND C{n}\nOUT Q{n}\n"));
    }
    src.push_str("LOD T4\nSOTU\nINC(W) D0\n");
    src.push_str("LOD M20\nJMP\nLOD M8125\nMOV(W) C4 D1\nJEND\n");
    let math = ["LOD M8125", "ADD(W) C0 D1 D2", "MOV(W) T1 D3"];
    let mut count = src.lines().count();
    'fill: loop {
        for i in math {
            if count == 99 {
                break 'fill;
            }
            src.push_str(i);
            src.push('\n');
            count += 1;
        }
    }
    src.push_str("END\n");
    src
}

/// Ten statements a round: 16- and 32-bit adds, a multiply into PREG, a fixed division, a
/// shift, a read of PRODH and a conditional jump.
pub const TML_ARITHMETIC: &str = include_str!("tml_arithmetic.tml");
