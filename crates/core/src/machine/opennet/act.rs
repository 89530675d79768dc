//! The control instructions that the executor and the fast loop share: contacts that
//! compare, timers, counters, shift registers, word compares, word logic, shifts, BCD
//! conversion, MCS/MCR and JMP.

use super::program::{Bit, CounterKind, Op, Value};
use super::{Cycle, M8003, Mark, OpenNet, TimerState};
use crate::machine::plc::accumulate;

impl OpenNet {
    /// The instructions of the PLC's control: contacts that compare, timers, counters, shift
    /// registers, the comparisons and word instructions, MCS/MCR and JMP/JEND. The executor
    /// and the fast loop both run them here; `record` keeps the REP cycles and the box's
    /// state before for the explanation. Returns where a taken jump continues.
    #[inline(always)]
    pub(crate) fn act(&mut self, index: usize, op: Op, record: bool) -> Option<u32> {
        let input = self.rlo && self.mc;
        match op {
            Op::Compare {
                counter,
                n,
                value,
                at_least,
            } => {
                let x = if counter {
                    self.counters.get(n as usize).map_or(0, |c| c.current)
                } else {
                    self.d.get(n as usize).copied().unwrap_or(0)
                };
                let v = self.value(value);
                self.load_contact(index, if at_least { x >= v } else { x == v });
            }
            Op::Timer { kind, n, preset } => {
                let scan_ms = self.time.scan_ms;
                let preset_now = match preset {
                    Value::Reg(_) => Some(self.value(preset)),
                    Value::Const(_) => None,
                };
                let t = self.timers.get_mut(n as usize)?;
                if record {
                    self.box_before = (t.current, t.output);
                }
                if let Some(p) = preset_now {
                    t.preset = p;
                }
                if !input {
                    *t = TimerState {
                        preset: t.preset,
                        current: t.preset,
                        ..TimerState::default()
                    };
                } else {
                    if t.running {
                        let (units, left) = accumulate(t.elapsed_ms, scan_ms, kind.increment_ms());
                        t.current = u64::from(t.current).saturating_sub(units) as u16;
                        t.elapsed_ms = left;
                    } else {
                        // The first powered execution starts timing and counts no time.
                        t.running = true;
                        t.current = t.preset;
                        t.elapsed_ms = 0;
                    }
                    t.output = t.current == 0;
                }
            }
            Op::Counter {
                kind,
                n,
                preset,
                pulses,
            } => {
                // The inputs in program order: the last is RLO, the others come off the stack.
                let last = self.rlo;
                let second = self.blocks.pop().unwrap_or(false);
                let (a, b, c) = if kind == CounterKind::Cnt {
                    (second, last, false)
                } else {
                    (self.blocks.pop().unwrap_or(false), second, last)
                };
                let preset_now = match preset {
                    Value::Reg(_) => Some(self.value(preset)),
                    Value::Const(_) => None,
                };
                let p = pulses as usize;
                if record {
                    self.legs = [a, b, c];
                    if let Some(cn) = self.counters.get(n as usize) {
                        self.box_before = (cn.current, cn.output);
                    }
                }
                let mc = self.mc;
                let rises = if mc {
                    match kind {
                        CounterKind::Cnt | CounterKind::Cud => (self.pulses.rose(p, b), false),
                        CounterKind::Cdp => (self.pulses.rose(p, b), self.pulses.rose(p + 1, c)),
                    }
                } else {
                    // MC off: the memories forget, so a pulse on when MC returns counts.
                    self.pulses.rose(p, false);
                    if kind == CounterKind::Cdp {
                        self.pulses.rose(p + 1, false);
                    }
                    (false, false)
                };
                let cn = self.counters.get_mut(n as usize)?;
                if let Some(v) = preset_now {
                    cn.preset = v;
                }
                if !mc {
                    cn.output = false;
                    return None;
                }
                match kind {
                    CounterKind::Cnt => {
                        if a {
                            cn.current = 0;
                            cn.output = false;
                        } else {
                            if rises.0 && cn.current < cn.preset {
                                cn.current += 1;
                            }
                            cn.output = cn.current >= cn.preset;
                        }
                    }
                    CounterKind::Cdp | CounterKind::Cud => {
                        if a {
                            cn.current = cn.preset;
                        } else {
                            let (up, down) = if kind == CounterKind::Cdp {
                                rises
                            } else {
                                (rises.0 && c, rises.0 && !c)
                            };
                            if up && !down {
                                cn.current = cn.current.wrapping_add(1);
                            } else if down && !up {
                                cn.current = cn.current.wrapping_sub(1);
                            }
                        }
                        cn.output = cn.current == 0;
                    }
                }
            }
            Op::ShiftRegister {
                down,
                first,
                len,
                pulses,
            } => {
                let data = self.rlo;
                let pulse = self.blocks.pop().unwrap_or(false);
                let reset = self.blocks.pop().unwrap_or(false);
                if record {
                    self.legs = [reset, pulse, data];
                }
                if !self.mc {
                    self.pulses.rose(pulses as usize, false);
                    return None;
                }
                let rise = self.pulses.rose(pulses as usize, pulse);
                let (from, to) = (first as usize, (first + len) as usize);
                let bits = self.r.get_mut(from..to)?;
                if reset {
                    bits.fill(false);
                } else if rise {
                    let top = bits.len() - 1;
                    if down {
                        bits.copy_within(1.., 0);
                        bits[top] = data;
                    } else {
                        bits.copy_within(..top, 1);
                        bits[0] = data;
                    }
                }
            }
            Op::WordCompare {
                rel,
                ty,
                a,
                b,
                c,
                dst: (area, at),
                dst_repeat,
                rep,
            } if input => {
                let w = ty.words();
                for k in 0..u32::from(rep) {
                    let (ao, bo) = (Self::offset(&a, w, k), Self::offset(&b, w, k));
                    let x = ty.value(self.read_word(&a, w, ao));
                    let y = ty.value(self.read_word(&b, w, bo));
                    let z = ty.value(self.read_word(&c, w, Self::offset(&c, w, k)));
                    let on = rel.holds(x, y, z);
                    let point = at + if dst_repeat { k } else { 0 };
                    self.set_bit(Bit::Point(area, point), on);
                    if record {
                        self.last_cycles.push(Cycle {
                            exact: z,
                            stored: u32::from(on),
                            dst_at: point - at,
                            ..Cycle::read(x, y, ao, bo)
                        });
                    }
                }
            }
            Op::WordLogic {
                op: logic,
                ty,
                a,
                b,
                dst,
                rep,
            } if input => {
                let w = ty.words();
                for k in 0..u32::from(rep) {
                    let (ao, bo, dof) = (
                        Self::offset(&a, w, k),
                        Self::offset(&b, w, k),
                        Self::offset(&dst, w, k),
                    );
                    let x = self.read_word(&a, w, ao);
                    let y = self.read_word(&b, w, bo);
                    let v = logic.apply(x, y);
                    self.write_word(&dst, w, dof, v);
                    if record {
                        self.last_cycles.push(Cycle {
                            stored: v,
                            dst_at: dof,
                            ..Cycle::read(i64::from(x), i64::from(y), ao, bo)
                        });
                    }
                }
            }
            Op::Shift { left, ty, word, by } if input => {
                let w = ty.words();
                let bits = ty.bits();
                let by = u32::from(by);
                let old = self.read_word(&word, w, 0);
                let mask = if bits == 32 {
                    u32::MAX
                } else {
                    (1 << bits) - 1
                };
                let (new, out) = if left {
                    ((old << by) & mask, old >> (bits - by) & 1)
                } else {
                    (old >> by, old >> (by - 1) & 1)
                };
                self.write_word(&word, w, 0, new);
                self.special[M8003] = out == 1;
                if record {
                    self.last_cycles.push(Cycle {
                        stored: new,
                        ..Cycle::read(i64::from(old), i64::from(by), 0, 0)
                    });
                }
            }
            Op::Convert {
                to_bcd,
                ty,
                src,
                dst,
                rep,
            } if input => {
                let w = ty.words();
                for k in 0..u32::from(rep) {
                    let (so, dof) = (Self::offset(&src, w, k), Self::offset(&dst, w, k));
                    let v = self.read_word(&src, w, so);
                    let digits = 4 * w;
                    let result = if to_bcd {
                        (u64::from(v) < 10u64.pow(digits))
                            .then(|| crate::machine::plc::to_bcd(u64::from(v)))
                            .ok_or("bcd_range")
                    } else {
                        crate::machine::plc::bcd_value(v, digits)
                            .map(|x| x as u32)
                            .ok_or("bcd_digit")
                    };
                    match result {
                        Ok(out) => self.write_word(&dst, w, dof, out),
                        Err(kind) => self.record_error_at(index, kind),
                    }
                    if record {
                        self.last_cycles.push(Cycle {
                            stored: result.unwrap_or(0),
                            error: result.err(),
                            dst_at: dof,
                            ..Cycle::read(i64::from(v), 0, so, 0)
                        });
                    }
                }
            }
            Op::Mcs(end) => {
                self.mc = input;
                // Until its MCR every instruction runs with MC = 0 (no jump is taken then).
                if !input && (end as usize) < self.marks.len() {
                    self.marks[index + 1..end as usize].fill(Mark::MasterOff);
                }
            }
            Op::Mcr => self.mc = true,
            Op::Jmp(to) if input && (to as usize) < self.marks.len() => {
                self.marks[index + 1..to as usize].fill(Mark::Jumped);
                return Some(to);
            }
            _ => {}
        }
        None
    }
}
