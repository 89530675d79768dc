//! The headless runner of spec §8: run a program to its end, a fault or a tick limit, with an
//! input timeline, and report the final state as text or as one JSON object.

use std::fmt::Write as _;
use std::sync::Arc;

use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};

use crate::debugger::history::{Edit, UserEvent};
use crate::machine::silverlode::{SilverLode, assemble};
use crate::machine::{Diagnostic, FaultInfo, Machine, RunState};
use crate::session::{DIALECT, FORMAT_VERSION, Session};

pub const DEFAULT_MAX_TICKS: u64 = 10_000_000;

/// An input toggle: input `index` (0-based) flips when the tick counter equals `tick`.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct InputToggle {
    pub tick: u64,
    pub input: usize,
}

/// Parse `IOk=T1,T2,...` (k in 1..=3) into toggles.
pub fn parse_input_spec(spec: &str) -> Result<Vec<InputToggle>, String> {
    let (name, ticks) = spec
        .split_once('=')
        .ok_or_else(|| format!("--input '{spec}': expected IOk=T1,T2,..."))?;
    let input = match name.trim().to_ascii_uppercase().as_str() {
        "IO1" => 0,
        "IO2" => 1,
        "IO3" => 2,
        other => {
            return Err(format!(
                "--input '{spec}': unknown input '{other}' (IO1, IO2 or IO3)"
            ));
        }
    };
    ticks
        .split(',')
        .map(|t| {
            let t = t.trim().replace('_', "");
            t.parse::<u64>()
                .map(|tick| InputToggle { tick, input })
                .map_err(|_| format!("--input '{spec}': '{t}' is not a tick number"))
        })
        .collect()
}

/// Input toggles as timeline events that set each input's level (inputs start low).
pub fn toggles_to_events(toggles: &[InputToggle]) -> Vec<UserEvent> {
    let mut toggles = toggles.to_vec();
    toggles.sort();
    let mut levels = [false; 3];
    toggles
        .iter()
        .filter(|t| t.input < 3)
        .map(|t| {
            levels[t.input] = !levels[t.input];
            UserEvent {
                tick: t.tick,
                edit: Edit::Input {
                    input: t.input,
                    high: levels[t.input],
                },
            }
        })
        .collect()
}

/// Run `machine` until it stops or reaches `max_ticks`, applying each event when the tick
/// counter equals its tick (before that tick runs). Events before the current tick count as
/// already applied. The same rule as the debugger's timeline, so a run and a session agree.
pub fn run_events(machine: &mut SilverLode, events: &[UserEvent], max_ticks: u64) {
    let mut events = events.to_vec();
    events.sort_by_key(|e| e.tick);
    let mut next = events.partition_point(|e| e.tick < machine.ticks());
    loop {
        while let Some(e) = events.get(next).filter(|e| e.tick <= machine.ticks()) {
            e.edit.apply(machine);
            next += 1;
        }
        let until = events
            .get(next)
            .map_or(max_ticks, |e| e.tick.min(max_ticks));
        machine.run_until(until, |_| false);
        if !machine.run_state().is_live() || machine.ticks() >= max_ticks {
            return;
        }
    }
}

/// Run `machine` until it stops or reaches `max_ticks`, toggling inputs on the way.
pub fn run_with_inputs(machine: &mut SilverLode, toggles: &[InputToggle], max_ticks: u64) {
    run_events(machine, &toggles_to_events(toggles), max_ticks);
}

/// A session that reproduces a headless run: the program, its events, the tick it stopped at.
pub fn session_of_run(
    name: &str,
    path: Option<&std::path::Path>,
    source: &str,
    machine: &SilverLode,
    events: Vec<UserEvent>,
) -> Session {
    Session {
        format: FORMAT_VERSION,
        dialect: DIALECT.to_string(),
        program_name: name.to_string(),
        program_path: path.map(std::path::Path::to_path_buf),
        program: source.to_string(),
        servo: machine.settings(),
        events,
        tick: machine.ticks(),
        furthest: machine.ticks(),
        ..Session::default()
    }
}

/// The final report, in the JSON shape of spec §8.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    pub dialect: &'static str,
    pub status: &'static str,
    pub ticks: u64,
    pub steps: u64,
    pub fault: Option<FaultInfo>,
    #[serde(serialize_with = "registers_in_order")]
    pub registers: Vec<i32>,
    pub isw: u16,
    pub psw: u16,
    pub queues: Vec<QueueReport>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QueueReport {
    pub base: usize,
    pub size: usize,
    pub len: usize,
    pub head: usize,
    pub tail: usize,
    /// From the tail (oldest) to the head (newest).
    pub items: Vec<i32>,
}

fn registers_in_order<S: Serializer>(regs: &[i32], s: S) -> Result<S::Ok, S::Error> {
    let mut map = s.serialize_map(Some(regs.len()))?;
    for (i, v) in regs.iter().enumerate() {
        map.serialize_entry(&i.to_string(), v)?;
    }
    map.end()
}

impl Report {
    pub fn of(m: &SilverLode) -> Report {
        let status = match m.run_state() {
            RunState::Ended => "ended",
            RunState::Faulted => "faulted",
            _ => "limit",
        };
        Report {
            dialect: m.dialect(),
            status,
            ticks: m.ticks(),
            steps: m.steps(),
            fault: m.fault(),
            registers: m.regs().to_vec(),
            isw: m.isw(),
            psw: m.psw(),
            queues: m
                .queues()
                .into_iter()
                .filter_map(|q| {
                    // A header the program overwrote is not a queue any more; the runner lists
                    // only queues it can decode.
                    let h = q.header?;
                    Some(QueueReport {
                        base: q.base,
                        size: h.size,
                        len: h.len,
                        head: h.head,
                        tail: h.tail,
                        items: h.items,
                    })
                })
                .collect(),
        }
    }

    /// Exit code of spec §8: 0 ended, 1 faulted, 3 tick limit.
    pub fn exit_code(&self) -> i32 {
        match self.status {
            "ended" => 0,
            "faulted" => 1,
            _ => 3,
        }
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
    }

    /// A summary for people: status, counters, fault, non-zero registers, queues.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "status: {}  ticks: {} ({:.3} ms)  steps: {}",
            self.status,
            self.ticks,
            self.ticks as f64 * 0.12,
            self.steps
        );
        if let Some(f) = &self.fault {
            let _ = writeln!(out, "fault: {} at line {}: {}", f.kind, f.line, f.message);
        }
        let _ = writeln!(
            out,
            "ISW: 0x{:04X} ({:016b})  PSW: 0x{:04X} ({:016b})",
            self.isw, self.isw, self.psw, self.psw
        );
        let nonzero: Vec<String> = self
            .registers
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0)
            .map(|(i, v)| format!("R{i}={v}"))
            .collect();
        if nonzero.is_empty() {
            let _ = writeln!(out, "registers: all zero");
        } else {
            let _ = writeln!(out, "registers (non-zero): {}", nonzero.join(" "));
        }
        for q in &self.queues {
            let _ = writeln!(
                out,
                "queue R{}: {}/{} head {} tail {} items (oldest first) {:?}",
                q.base, q.len, q.size, q.head, q.tail, q.items
            );
        }
        out
    }
}

/// Assemble `source` and build a machine, or return every diagnostic.
pub fn load(source: &str) -> Result<SilverLode, Vec<Diagnostic>> {
    assemble(source).map(|p| SilverLode::new(Arc::new(p)))
}
