//! Word operands: the patterns of registers, bit words, timers and counters read and
//! written, one word or a pair, advanced per REP cycle; presets and compared values.

use super::OpenNet;
use super::program::{Value, Word};

impl OpenNet {
    /// The pattern of `words` words at `w`, advanced by `offset` words.
    #[inline]
    pub fn read_word(&self, w: &Word, words: u32, offset: u32) -> u32 {
        match *w {
            Word::Const(v) => v,
            Word::Reg { n, .. } => {
                let at = (n + offset) as usize;
                let hi = u32::from(self.d.get(at).copied().unwrap_or(0));
                if words == 1 {
                    hi
                } else {
                    // The upper word is in the lower-numbered register.
                    (hi << 16) | u32::from(self.d.get(at + 1).copied().unwrap_or(0))
                }
            }
            Word::Bits { area, index, .. } => {
                let start = (index + offset * 16) as usize;
                let bits = self.area(area);
                (0..words * 16).fold(0, |acc, i| {
                    acc | (u32::from(bits.get(start + i as usize).copied().unwrap_or(false)) << i)
                })
            }
            // A timer or counter as a source is its current value (spec §4.3).
            Word::Timer { n, .. } => self.box_words(words, (n + offset) as usize, |m, i| {
                m.timers.get(i).map_or(0, |t| t.current)
            }),
            Word::Counter { n, .. } => self.box_words(words, (n + offset) as usize, |m, i| {
                m.counters.get(i).map_or(0, |c| c.current)
            }),
        }
    }

    /// `words` consecutive timer or counter values from `at`, the first the upper word.
    fn box_words(&self, words: u32, at: usize, get: impl Fn(&Self, usize) -> u16) -> u32 {
        let hi = u32::from(get(self, at));
        if words == 1 {
            hi
        } else {
            (hi << 16) | u32::from(get(self, at + 1))
        }
    }

    #[inline]
    pub fn write_word(&mut self, w: &Word, words: u32, offset: u32, value: u32) {
        match *w {
            Word::Const(_) => {}
            Word::Reg { n, .. } => {
                let at = (n + offset) as usize;
                if words == 1 {
                    if let Some(r) = self.d.get_mut(at) {
                        *r = value as u16;
                    }
                } else {
                    if let Some(r) = self.d.get_mut(at) {
                        *r = (value >> 16) as u16;
                    }
                    if let Some(r) = self.d.get_mut(at + 1) {
                        *r = value as u16;
                    }
                }
            }
            Word::Bits { area, index, .. } => {
                let start = (index + offset * 16) as usize;
                let bits = self.area_mut(area);
                for i in 0..(words * 16) as usize {
                    if let Some(b) = bits.get_mut(start + i) {
                        *b = value >> i & 1 == 1;
                    }
                }
            }
            // A timer or counter as a destination takes the value as its preset (spec §4.3); a
            // pair keeps its upper word in the lower number, as registers do.
            Word::Timer { n, .. } | Word::Counter { n, .. } => {
                let timer = matches!(w, Word::Timer { .. });
                let at = (n + offset) as usize;
                let parts: &[(usize, u16)] = if words == 1 {
                    &[(at, value as u16)]
                } else {
                    &[(at, (value >> 16) as u16), (at + 1, value as u16)]
                };
                for &(i, v) in parts {
                    if timer {
                        if let Some(t) = self.timers.get_mut(i) {
                            t.preset = v;
                        }
                    } else if let Some(c) = self.counters.get_mut(i) {
                        c.preset = v;
                    }
                }
            }
        }
    }

    /// The offset of a word operand in REP cycle `c`: `(R)` operands advance by their block.
    #[inline]
    pub(super) fn offset(w: &Word, block: u32, c: u32) -> u32 {
        if w.repeats() { c * block } else { 0 }
    }

    /// A preset or compared value now.
    #[inline]
    pub(super) fn value(&self, v: Value) -> u16 {
        match v {
            Value::Const(c) => c,
            Value::Reg(n) => self.d.get(n as usize).copied().unwrap_or(0),
        }
    }
}
