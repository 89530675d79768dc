//! The plot channels: the user's choice by location name (or watch expression), resolved
//! against each assembled program; choosing them rebuilds the trace.

use super::history::Mark;
use super::trace::{self, Channel, MAX_CHANNELS};
use super::{Debugger, Dialect, StopWhen, expr, run_into_stop};
use crate::machine::{Format, Loc, MachineView};

/// A plot channel as the user chose it: a location name, a legend and a plot group.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ChannelChoice {
    pub location: String,
    #[serde(default)]
    pub label: String,
    #[serde(default)]
    pub group: u8,
}

impl ChannelChoice {
    /// What a new program's plot starts on: for a PLC, the outputs and relays it drives (in
    /// one plot) and the inputs it reads (in a second), four at most; otherwise, and for a PLC program without bits, the dialect's defaults (a servo's
    /// target and actual position).
    pub fn for_program(dialect: &Dialect, m: &dyn MachineView) -> Vec<ChannelChoice> {
        const MOST: usize = 4;
        if !m.is_plc() {
            return ChannelChoice::defaults(dialect);
        }
        let kind_of = |loc: Loc| m.spaces().get(usize::from(loc.space)).map(|s| s.kind);
        let used = m.used();
        let bits = |kind: crate::machine::SpaceKind| {
            used.iter()
                .copied()
                .filter(move |&loc| kind_of(loc) == Some(kind))
                .filter(|&loc| m.info(loc).is_some_and(|i| i.width == 1))
        };
        let mut driven: Vec<Loc> = bits(crate::machine::SpaceKind::Bits).take(MOST).collect();
        let read: Vec<Loc> = bits(crate::machine::SpaceKind::Inputs).take(MOST).collect();
        // One row at least for an input, when the program reads any.
        if !read.is_empty() && driven.len() == MOST {
            driven.pop();
        }
        let rows = (driven.into_iter().map(|loc| (loc, 0)))
            .chain(read.into_iter().map(|loc| (loc, 1)))
            .take(MOST);
        let chosen: Vec<ChannelChoice> = rows
            .filter_map(|(loc, group)| {
                Some(ChannelChoice {
                    location: m.info(loc)?.name,
                    label: String::new(),
                    group,
                })
            })
            .collect();
        if chosen.is_empty() {
            ChannelChoice::defaults(dialect)
        } else {
            chosen
        }
    }

    pub fn defaults(dialect: &Dialect) -> Vec<ChannelChoice> {
        dialect
            .default_channels
            .iter()
            .map(|c| ChannelChoice {
                location: c.location.to_string(),
                label: c.label.to_string(),
                group: c.group,
            })
            .collect()
    }
}

impl Debugger {
    pub(super) fn resolve_channels(&self, m: &dyn MachineView) -> Vec<Channel> {
        self.channel_names
            .iter()
            .filter_map(|c| {
                let label = |name: &str| {
                    if c.label.is_empty() {
                        name.to_string()
                    } else {
                        c.label.clone()
                    }
                };
                if let Some(loc) = m.find(&c.location) {
                    let info = m.info(loc)?;
                    let reading = info.reading();
                    return Some(Channel {
                        loc,
                        label: label(&info.name),
                        name: info.name,
                        width: info.width,
                        // A word its dialect reads as signed (an OpenNet D of type I) plots so.
                        signed: info.signed || reading == Format::Signed,
                        reading,
                        group: c.group,
                        expr: None,
                    });
                }
                // Not a location: a watch expression plotted as a channel.
                let expr = expr::Expr::compile(&c.location, m).ok()?;
                Some(Channel {
                    loc: Loc::new(0, 0),
                    label: label(expr.text()),
                    name: expr.text().to_string(),
                    width: 64,
                    signed: true,
                    reading: Format::Signed,
                    group: c.group,
                    expr: Some(expr),
                })
            })
            .take(MAX_CHANNELS)
            .collect()
    }

    /// Choose the plot channels. The trace is rebuilt by replaying the recorded history.
    pub fn set_channels(&mut self, channels: Vec<ChannelChoice>) {
        self.channel_names = channels;
        self.channel_names.truncate(MAX_CHANNELS);
        for c in &mut self.channel_names {
            c.group = c.group.min(trace::PLOT_GROUPS - 1);
        }
        let here = self.pos();
        let furthest = self.furthest();
        let resolved = self.resolve_channels(self.engine.machine());
        let marks: Vec<Mark> = self.marks().to_vec();
        let stopped = self.engine.stopped();
        // Paused just before the instruction that stopped the run: stays before it.
        let before_stop =
            stopped && here == furthest && self.engine.machine().run_state().is_live();
        let mut engine = self.engine.restarted(self.events().to_vec(), resolved);
        engine.forward(furthest, &StopWhen::default());
        if stopped {
            run_into_stop(engine.as_mut());
        }
        for m in marks {
            engine.mark_at(m.at, m.kind, m.line);
        }
        if before_stop {
            engine.goto_live(here);
        } else {
            engine.goto(here);
        }
        self.engine = engine;
    }
}
