//! Timers and counters: the outputs that run whatever their rung's power (coils, PD, OROUT
//! and the boxes), each box's value, preset and status, and the rows of their panel.

use super::program::{self, Bit, CounterKind, Kind, Op, Preset, TimerKind};
use super::{Dl205, bcd_value, to_bcd};
use crate::machine::plc::accumulate;

impl Dl205 {
    /// An output that runs whatever its rung's power `p` (spec §5).
    pub(in crate::machine) fn always(&mut self, op: Op, p: bool) {
        match op {
            Op::Coil(b) => self.set_bit(b, p),
            Op::Pd(b, edge) => {
                let fired = self.edges.rose(edge as usize, p);
                self.set_bit(b, fired);
            }
            Op::OrOut(b, mark) => {
                let first = self
                    .orout_marks
                    .get_mut(mark as usize)
                    .is_some_and(|m| !std::mem::replace(m, true));
                let on = if first { p } else { self.bit(b) || p };
                self.set_bit(b, on);
            }
            Op::Timer(kind, n, preset) => {
                let (enable, reset) = if kind.accumulating() {
                    (self.leg(0), self.leg(1))
                } else {
                    (p, !p)
                };
                self.timer(kind, n, preset, enable, reset);
            }
            Op::Counter(kind, n, preset) => {
                let (up, down, reset) = match kind {
                    CounterKind::Cnt => (self.leg(0), false, self.leg(1)),
                    CounterKind::Sgcnt => (p, false, false),
                    CounterKind::Udc => (self.leg(0), self.leg(1), self.leg(2)),
                };
                self.counter(kind, n, preset, up, down, reset);
            }
            _ => {}
        }
    }

    /// Leg `i` of a multi-input box: the rung's i-th level, first STR first, inside the
    /// block's power.
    pub(super) fn leg(&self, i: usize) -> bool {
        self.block_power && self.bstack.get(i).copied().unwrap_or(false)
    }

    /// A box's current value: one word, or a pair (low word first).
    pub(super) fn box_value(&self, addr: u32, words: u32) -> u32 {
        if words == 2 {
            self.pair(addr)
        } else {
            u32::from(self.word(addr))
        }
    }

    fn set_box_value(&mut self, addr: u32, words: u32, value: u32) {
        self.set_word(addr, value as u16);
        if words == 2 {
            self.set_word(addr + 1, (value >> 16) as u16);
        }
    }

    pub(super) fn preset(&self, preset: Preset) -> u32 {
        match preset {
            Preset::K(k) => k,
            Preset::Word(a) => u32::from(self.word(a)),
            Preset::Pair(a) => self.pair(a),
        }
    }

    /// The status bit of a box: current value ≥ preset as raw patterns (spec §9.15); a
    /// non-BCD preset also sets SP75 (§9.16).
    fn box_done(&mut self, value: u32, preset: Preset, words: u32) -> bool {
        let preset = self.preset(preset);
        if bcd_value(preset, 4 * words).is_none() {
            self.non_bcd();
        }
        value >= preset
    }

    /// A timer's execution (spec §6.9): reset, count this scan once, status.
    fn timer(&mut self, kind: TimerKind, n: u32, preset: Preset, enable: bool, reset: bool) {
        let words = if kind.accumulating() { 2 } else { 1 };
        let i = n as usize;
        self.box_before = self.box_value(n, words);
        if reset {
            self.set_box_value(n, words, 0);
            self.t_ms[i] = 0;
            self.t_counted[i] = 0;
            self.t[i] = false;
            return;
        }
        let max: u64 = if words == 2 { 99_999_999 } else { 9_999 };
        if enable && self.t_counted[i] != self.tick + 1 {
            self.t_counted[i] = self.tick + 1;
            match bcd_value(self.box_value(n, words), 4 * words) {
                None => self.non_bcd(),
                Some(value) if value < max => {
                    let (units, left) = accumulate(self.t_ms[i], self.time.scan_ms, kind.unit_ms());
                    let value = (value + units).min(max);
                    self.t_ms[i] = if value == max { 0 } else { left };
                    self.set_box_value(n, words, to_bcd(value));
                }
                Some(_) => self.t_ms[i] = 0,
            }
        }
        let value = self.box_value(n, words);
        self.t[i] = self.box_done(value, preset, words);
    }

    /// A counter's execution (spec §6.9): count rises, reset, status.
    fn counter(
        &mut self,
        kind: CounterKind,
        n: u32,
        preset: Preset,
        up: bool,
        down: bool,
        reset: bool,
    ) {
        let words = if kind == CounterKind::Udc { 2 } else { 1 };
        let i = n as usize;
        let addr = program::current_word(Kind::Ct, n);
        self.box_before = self.box_value(addr, words);
        let (rose_up, rose_down) = self.ct_in[i].rises(up, down);
        if reset {
            self.set_box_value(addr, words, 0);
            self.ct[i] = false;
            return;
        }
        if rose_up != rose_down {
            let max: u64 = if words == 2 { 99_999_999 } else { 9_999 };
            match bcd_value(self.box_value(addr, words), 4 * words) {
                None => self.non_bcd(),
                Some(v) => {
                    let v = if rose_up {
                        (v + 1).min(max)
                    } else {
                        v.saturating_sub(1)
                    };
                    self.set_box_value(addr, words, to_bcd(v));
                }
            }
        }
        let value = self.box_value(addr, words);
        self.ct[i] = self.box_done(value, preset, words);
    }

    /// RST of a timer or counter bit: its box starts over (value word(s), time, status).
    pub(super) fn reset_box(&mut self, b: Bit) {
        let i = b.n as usize;
        let words = self.program.box_words(b);
        let addr = program::current_word(b.kind, b.n);
        if (addr + words) as usize <= self.v.len() {
            self.set_box_value(addr, words, 0);
        }
        if b.kind == Kind::T {
            self.t_ms[i] = 0;
            self.t_counted[i] = 0;
        }
        self.set_bit(b, false);
    }

    /// Every timer and counter box for the Timers & counters panel, in program order.
    pub fn boxes(&self) -> Vec<crate::machine::plc::BoxRow> {
        self.program
            .boxes
            .iter()
            .filter_map(|b| {
                let ins = self.program.instrs.get(b.instr)?;
                let (mnemonic, unit_ms) = match ins.op {
                    Op::Timer(k, ..) => (k.mnemonic(), Some(k.unit_ms())),
                    Op::Counter(k, ..) => (k.mnemonic(), None),
                    _ => return None,
                };
                let status = program::bit_name(b.status);
                let raw = self.box_value(program::current_word(b.status.kind, b.status.n), b.words);
                let digits = 4 * b.words;
                Some(crate::machine::plc::BoxRow {
                    title: format!("{mnemonic} {status}"),
                    preset_from: ins.text.split_whitespace().nth(2).unwrap_or("").to_string(),
                    preset: bcd_value(self.preset(b.preset), digits),
                    value_at: format!("{}A{:o}", b.status.kind.letter(), b.status.n),
                    value: bcd_value(raw, digits),
                    raw: u64::from(raw),
                    max: if b.words == 2 { 99_999_999 } else { 9_999 },
                    unit_ms,
                    done: self.bit(b.status),
                    line: ins.line,
                    countdown: None,
                    status,
                })
            })
            .collect()
    }
}
