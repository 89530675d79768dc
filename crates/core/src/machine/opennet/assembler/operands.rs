//! Operands: constants, I/Q/M/R points, timer and counter numbers, bits, words and values.

use super::{Error, MICRO3, Pass, REGISTERS, Token, err};
use crate::machine::opennet::program::{Area, BOXES, Bit, SPECIAL, Ty, Value, Word};

/// A number as written: decimal with sign, or hex digits then `h`. Returns (value, is hex).
pub(super) fn constant(text: &str) -> Option<(i64, bool)> {
    let lower = text.to_ascii_lowercase();
    if let Some(hex) = lower.strip_suffix('h') {
        if hex.is_empty() || hex.len() > 16 || !hex.chars().all(|c| c.is_ascii_hexdigit()) {
            return None;
        }
        return i64::from_str_radix(hex, 16).ok().map(|v| (v, true));
    }
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || digits.len() > 18 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    text.parse::<i64>().ok().map(|v| (v, false))
}

/// An operand token (a letter then digits, maybe `(R)`): (letter, number, repeat).
pub(super) fn operand(text: &str) -> Option<(char, u32, bool)> {
    let (body, repeat) = match text.len().checked_sub(3) {
        Some(cut) if text.is_char_boundary(cut) && text[cut..].eq_ignore_ascii_case("(R)") => {
            (&text[..cut], true)
        }
        _ => (text, false),
    };
    let mut chars = body.chars();
    let letter = chars.next()?.to_ascii_uppercase();
    let digits = chars.as_str();
    if !letter.is_ascii_alphabetic()
        || digits.is_empty()
        || digits.len() > 6
        || !digits.chars().all(|c| c.is_ascii_digit())
    {
        return None;
    }
    Some((letter, digits.parse().ok()?, repeat))
}

/// An I/Q/M/R point number → its index (IDEC numbering: the last digit of I/Q/M is octal).
pub(super) fn point(area: Area, n: u32, t: &Token) -> Result<u32, Error> {
    if area.octal() && n % 10 >= 8 {
        return err(
            t.col,
            t.text.len(),
            format!(
                "{}: the last digit of an {} number is octal (0–7)",
                t.text,
                area.letter()
            ),
        );
    }
    let index = if area.octal() { n / 10 * 8 + n % 10 } else { n };
    if index >= area.points() {
        let last = crate::machine::opennet::program::point_name(area, area.points() - 1);
        return err(
            t.col,
            t.text.len(),
            format!("{} is out of range ({}0–{last})", t.text, area.letter()),
        );
    }
    Ok(index)
}

/// A timer or counter number 0–255, with `span` numbers from it.
fn box_number(n: u32, span: u32, t: &Token) -> Result<u32, Error> {
    let letter = t.text.chars().next().unwrap_or('T').to_ascii_uppercase();
    if n >= BOXES {
        return err(
            t.col,
            t.text.len(),
            format!("{} is out of range ({letter}0–{letter}255)", t.text),
        );
    }
    if n + span > BOXES {
        return err(
            t.col,
            t.text.len(),
            format!("{} with its {span} word(s) runs past {letter}255", t.text),
        );
    }
    Ok(n)
}

pub(super) fn note_boxes(list: &mut Vec<u32>, n: u32, span: u32) {
    list.extend(n..n + span);
}

/// A bit operand; `output`: OUT/OUTN/SET/RST (no input, read-only special relay, T or C).
pub(super) fn bit(t: &Token, output: bool, pass: &mut Pass) -> Result<Bit, Error> {
    let Some((letter, n, repeat)) = operand(&t.text) else {
        return err(
            t.col,
            t.text.len(),
            format!("'{}' is not a bit operand (I, Q, M, R, T or C)", t.text),
        );
    };
    if repeat {
        return err(
            t.col,
            t.text.len(),
            "(R) belongs to advanced instructions with REP",
        );
    }
    let b = match letter {
        'I' if output => {
            return err(
                t.col,
                t.text.len(),
                format!("{} is an input: a program cannot write it", t.text),
            );
        }
        'I' => Bit::Point(Area::I, point(Area::I, n, t)?),
        'Q' => Bit::Point(Area::Q, point(Area::Q, n, t)?),
        'R' => Bit::Point(Area::R, point(Area::R, n, t)?),
        'M' if n >= 8000 => {
            let Some(i) = SPECIAL.iter().position(|&s| u32::from(s) == n) else {
                return err(
                    t.col,
                    t.text.len(),
                    format!(
                        "{} is a special relay not supported by servoscope yet (M8003, M8004, M8120–M8123 and M8125 are)",
                        t.text
                    ),
                );
            };
            if output && i >= 2 {
                return err(t.col, t.text.len(), format!("{} is read-only", t.text));
            }
            Bit::Special(i as u8)
        }
        'M' => {
            let index = point(Area::M, n, t)?;
            if output {
                pass.note_m_write(Area::M, index, 1);
            } else if MICRO3.iter().any(|&(m, ..)| m == n)
                && !pass.micro3_reads.iter().any(|r| r.0 == n)
            {
                pass.micro3_reads.push((n, pass.line, t.col, t.text.len()));
            }
            Bit::Point(Area::M, index)
        }
        'T' | 'C' if output => {
            let what = if letter == 'T' {
                "a timer's output: its timer"
            } else {
                "a counter's output: its counter"
            };
            return err(
                t.col,
                t.text.len(),
                format!("{} is {what} instruction sets it", t.text),
            );
        }
        'T' => {
            let n = box_number(n, 1, t)?;
            note_boxes(&mut pass.program.used_timers, n, 1);
            Bit::Timer(n)
        }
        'C' => {
            let n = box_number(n, 1, t)?;
            note_boxes(&mut pass.program.used_counters, n, 1);
            Bit::Counter(n)
        }
        'D' => {
            return err(
                t.col,
                t.text.len(),
                format!(
                    "{} is a data register: a bit instruction needs I, Q, M, R, T or C",
                    t.text
                ),
            );
        }
        'L' => {
            return err(
                t.col,
                t.text.len(),
                format!(
                    "{} is a link register (L), not supported by servoscope yet",
                    t.text
                ),
            );
        }
        _ => {
            return err(
                t.col,
                t.text.len(),
                format!(
                    "'{}' is not an operand{}",
                    t.text,
                    other_vendor_hint(&t.text)
                ),
            );
        }
    };
    if let Bit::Point(area, index) = b {
        pass.program.used_bits.push((area, index));
    }
    Ok(b)
}

/// What a word operand is for (spec §4.3).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Role {
    Source,
    Destination,
    /// SFTL/SFTR's S1: read and written, a D register or Q, M, R points.
    InPlace,
}

/// A word operand: `words` its block size; `rep` the repeat count.
pub(super) fn word(
    t: &Token,
    ty: Ty,
    role: Role,
    words: u32,
    rep: u32,
    pass: &mut Pass,
) -> Result<Word, Error> {
    let len = t.text.len();
    let writes = role != Role::Source;
    if let Some((letter, n, repeat)) = operand(&t.text) {
        let span = words * if repeat { rep } else { 1 };
        return match letter {
            'D' => {
                if (8000..8500).contains(&n) {
                    return err(
                        t.col,
                        len,
                        format!(
                            "{} is a special data register, not supported by servoscope yet",
                            t.text
                        ),
                    );
                }
                if n >= REGISTERS {
                    return err(t.col, len, format!("{} is out of range (D0–D7999)", t.text));
                }
                if n + span > REGISTERS {
                    return err(
                        t.col,
                        len,
                        format!("{} with its {span} word(s) runs past D7999", t.text),
                    );
                }
                pass.program.used_regs.extend(n..n + span);
                if ty.signed() {
                    // Each item's first word: an I word, or the upper (sign) word of an L pair.
                    pass.program
                        .signed_regs
                        .extend((n..n + span).step_by(words.max(1) as usize));
                }
                Ok(Word::Reg { n, repeat })
            }
            'I' | 'Q' | 'M' | 'R' => {
                let area = match letter {
                    'I' if writes => {
                        return err(
                            t.col,
                            len,
                            format!("{} is an input: it cannot be a destination", t.text),
                        );
                    }
                    'I' => Area::I,
                    'Q' => Area::Q,
                    'R' => Area::R,
                    _ => Area::M,
                };
                if area == Area::M && n >= 8000 {
                    return err(
                        t.col,
                        len,
                        format!("{}: special relays are never word operands", t.text),
                    );
                }
                let index = point(area, n, t)?;
                if index + span * 16 > area.points() {
                    let last =
                        crate::machine::opennet::program::point_name(area, area.points() - 1);
                    return err(
                        t.col,
                        len,
                        format!("{} with its {} points runs past {last}", t.text, span * 16),
                    );
                }
                pass.program
                    .used_bits
                    .extend((index..index + span * 16).map(|i| (area, i)));
                if writes {
                    pass.note_m_write(area, index, span * 16);
                }
                Ok(Word::Bits {
                    area,
                    index,
                    repeat,
                })
            }
            'T' | 'C' => {
                let what = if letter == 'T' { "timer" } else { "counter" };
                if role == Role::InPlace {
                    return err(
                        t.col,
                        len,
                        format!("{} is a {what}: this operand takes D, Q, M or R", t.text),
                    );
                }
                if ty.words() != 1 {
                    return err(
                        t.col,
                        len,
                        format!(
                            "{} is a {what}: T and C words go with type W or I, not {}",
                            t.text,
                            ty.letter()
                        ),
                    );
                }
                let n = box_number(n, span, t)?;
                if letter == 'T' {
                    note_boxes(&mut pass.program.used_timers, n, span);
                    Ok(Word::Timer { n, repeat })
                } else {
                    note_boxes(&mut pass.program.used_counters, n, span);
                    Ok(Word::Counter { n, repeat })
                }
            }
            'L' => err(
                t.col,
                len,
                format!(
                    "{} is a link register (L), not supported by servoscope yet",
                    t.text
                ),
            ),
            _ => err(
                t.col,
                len,
                format!(
                    "'{}' is not an operand (D, I, Q, M, R, T, C or a constant){}",
                    t.text,
                    other_vendor_hint(&t.text)
                ),
            ),
        };
    }
    if t.text.to_ascii_uppercase().ends_with("(R)") {
        return err(t.col, len, "(R) cannot follow a constant");
    }
    let Some((v, hex)) = constant(&t.text) else {
        return err(
            t.col,
            len,
            format!("malformed operand or constant '{}'", t.text),
        );
    };
    if writes {
        return err(t.col, len, "a constant cannot be a destination");
    }
    let pattern = if hex {
        if v >> ty.bits() != 0 {
            return err(
                t.col,
                len,
                format!("{} does not fit {} bits", t.text, ty.bits()),
            );
        }
        v as u32
    } else {
        if v < ty.min() || v > ty.max() {
            return err(
                t.col,
                len,
                format!(
                    "{} is out of range for type {} ({} … {})",
                    t.text,
                    ty.letter(),
                    ty.min(),
                    ty.max()
                ),
            );
        }
        v as u32 & if ty.words() == 1 { 0xFFFF } else { u32::MAX }
    };
    Ok(Word::Const(pattern))
}

/// A preset or compared value: a constant 0–65535 (`0h`–`FFFFh`) or a data register.
pub(super) fn value(t: &Token, pass: &mut Pass) -> Result<Value, Error> {
    let len = t.text.len();
    if let Some((letter, n, repeat)) = operand(&t.text) {
        if repeat {
            return err(t.col, len, "(R) belongs to advanced instructions with REP");
        }
        if letter != 'D' {
            return err(
                t.col,
                len,
                format!(
                    "{}: a value is a constant 0–65535 or a data register (D)",
                    t.text
                ),
            );
        }
        if (8000..8500).contains(&n) {
            return err(
                t.col,
                len,
                format!(
                    "{} is a special data register, not supported by servoscope yet",
                    t.text
                ),
            );
        }
        if n >= REGISTERS {
            return err(t.col, len, format!("{} is out of range (D0–D7999)", t.text));
        }
        pass.program.used_regs.push(n);
        return Ok(Value::Reg(n));
    }
    match constant(&t.text) {
        Some((v, _)) if (0..=0xFFFF).contains(&v) => Ok(Value::Const(v as u16)),
        Some(_) => err(
            t.col,
            len,
            format!("{} is out of range for a value (0–65535)", t.text),
        ),
        None => err(
            t.col,
            len,
            format!(
                "malformed value '{}': a constant 0–65535 or a data register",
                t.text
            ),
        ),
    }
}

/// The timer or counter operand of a timer, counter or CC instruction.
pub(super) fn box_operand(t: &Token, want: char, mnemonic: &str) -> Result<u32, Error> {
    match operand(&t.text) {
        Some((letter, n, false)) if letter == want => box_number(n, 1, t),
        _ => {
            let what = if want == 'T' {
                "a timer T0–T255"
            } else {
                "a counter C0–C255"
            };
            err(
                t.col,
                t.text.len(),
                format!("{mnemonic} needs {what}, not '{}'", t.text),
            )
        }
    }
}

/// One point a comparison writes: a Q, M or R bit, with `span` points from it.
pub(super) fn dest_point(
    t: &Token,
    span: u32,
    pass: &mut Pass,
) -> Result<((Area, u32), bool), Error> {
    let len = t.text.len();
    let Some((letter, n, repeat)) = operand(&t.text) else {
        return err(
            t.col,
            len,
            format!(
                "'{}': a comparison's result goes to a Q, M or R bit",
                t.text
            ),
        );
    };
    let area = match letter {
        'Q' => Area::Q,
        'M' if n < 8000 => Area::M,
        'R' => Area::R,
        _ => {
            return err(
                t.col,
                len,
                format!("{}: a comparison's result goes to a Q, M or R bit", t.text),
            );
        }
    };
    let index = point(area, n, t)?;
    let span = if repeat { span } else { 1 };
    if index + span > area.points() {
        let last = crate::machine::opennet::program::point_name(area, area.points() - 1);
        return err(
            t.col,
            len,
            format!("{} with its {span} points runs past {last}", t.text),
        );
    }
    pass.program
        .used_bits
        .extend((index..index + span).map(|i| (area, i)));
    pass.note_m_write(area, index, span);
    Ok(((area, index), repeat))
}

/// For a DL205 (or generic PLC) name in an OpenNet program, the OpenNet one: outputs are Q,
/// inputs I, internal relays M.
fn other_vendor_hint(text: &str) -> String {
    let upper = text.to_ascii_uppercase();
    let digits = upper.trim_start_matches(|c: char| c.is_ascii_alphabetic());
    let letters = &upper[..upper.len() - digits.len()];
    let (kind, letter) = match letters {
        "Y" => ("outputs", "Q"),
        "X" => ("inputs", "I"),
        "C" if digits.is_empty() => return String::new(),
        "V" => ("data registers", "D"),
        _ => return String::new(),
    };
    format!(": OpenNet's {kind} are {letter} ({letter}{digits})")
}
