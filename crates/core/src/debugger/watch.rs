//! Watches: expressions in the condition language, each shown in a format of its own at the
//! current position, and plotted as a channel on request.

use super::expr::{Expr, ExprError};
use super::{ChannelChoice, Debugger, trace::MAX_CHANNELS};
use crate::machine::Format;

/// A watch as the user typed it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Watch {
    pub expr: String,
    pub format: Format,
}

impl Default for Watch {
    fn default() -> Self {
        Watch {
            expr: String::new(),
            format: Format::Signed,
        }
    }
}

impl Debugger {
    pub fn watches(&self) -> &[Watch] {
        &self.watches
    }

    /// Add a watch (kept even when it does not compile, so the user can fix it).
    pub fn add_watch(&mut self, expr: impl Into<String>, format: Format) -> usize {
        self.watches.push(Watch {
            expr: expr.into().trim().to_string(),
            format,
        });
        self.watches.len() - 1
    }

    pub fn update_watch(&mut self, index: usize, watch: Watch) {
        if let Some(slot) = self.watches.get_mut(index) {
            *slot = watch;
        }
    }

    pub fn remove_watch(&mut self, index: usize) {
        if index < self.watches.len() {
            self.watches.remove(index);
        }
    }

    pub fn set_watches(&mut self, watches: Vec<Watch>) {
        self.watches = watches;
    }

    /// The width of the one location a watch names, if it names just one (`V2000`, `counts`).
    pub fn watch_width(&self, index: usize) -> Option<u8> {
        let watch = self.watches.get(index)?;
        let loc = self.find(&watch.expr)?;
        Some(self.machine().info(loc)?.width)
    }

    /// The format a new watch of `expr` starts in: a location's own reading (a DL205 word in
    /// BCD, a TML fixed in Q16.16), else signed.
    pub fn watch_format_for(&self, expr: &str) -> Format {
        self.find(expr.trim())
            .and_then(|loc| self.machine().info(loc))
            .map_or(Format::Signed, |info| info.reading())
    }

    /// Where a watch's arithmetic goes past what the machine's registers hold: watches
    /// compute in 64 bits, so `R20 * R21` shows the exact product where the machine's 32-bit
    /// multiply wraps. `None` for a plain location, or a value that fits the widest location
    /// the expression reads; else what that width would hold ("in 32 bits it would wrap to
    /// -1294967296").
    pub fn watch_wrap_note(&self, index: usize) -> Option<String> {
        let watch = self.watches.get(index)?;
        if self.find(watch.expr.trim()).is_some() {
            return None;
        }
        let m = self.machine();
        let expr = super::expr::Expr::compile(&watch.expr, m).ok()?;
        let infos: Vec<_> = expr.locations().filter_map(|loc| m.info(loc)).collect();
        let width = infos.iter().map(|i| i.width).max()?;
        if width >= 64 || width <= 1 {
            return None;
        }
        let value = expr.eval(m);
        let signed = infos.iter().any(|i| i.signed);
        let fits = if signed {
            let half = 1i64 << (width - 1);
            (-half..half).contains(&value)
        } else {
            (0..1i64 << width).contains(&value)
        };
        if fits {
            return None;
        }
        let raw = value as u64 & crate::machine::value::mask(width);
        let wrapped = if signed {
            crate::machine::value::sign_extend(raw, width).to_string()
        } else {
            raw.to_string()
        };
        Some(format!(
            "computed in 64 bits: a {width}-bit register would hold {wrapped} (it wraps)"
        ))
    }

    /// The watch's value at the current position, or why it has none.
    pub fn watch_value(&self, index: usize) -> Result<i64, ExprError> {
        let watch = self.watches.get(index).ok_or_else(|| ExprError {
            col: 1,
            message: "no such watch".to_string(),
        })?;
        self.evaluate(&watch.expr)
    }

    /// Any expression's value at the current position.
    pub fn evaluate(&self, text: &str) -> Result<i64, ExprError> {
        Ok(Expr::compile(text, self.machine())?.eval(self.machine()))
    }

    /// Plot the watch as a channel on a plot of its own (the trace is rebuilt from the
    /// recorded history). False when it does not compile or every channel is taken.
    pub fn plot_watch(&mut self, index: usize) -> bool {
        let Some(watch) = self.watches.get(index) else {
            return false;
        };
        if Expr::compile(&watch.expr, self.machine()).is_err() {
            return false;
        }
        let mut channels = self.channel_names.clone();
        if channels.len() >= MAX_CHANNELS {
            return false;
        }
        if channels.iter().any(|c| c.location == watch.expr) {
            return true;
        }
        let group = channels.iter().map(|c| c.group).max().map_or(0, |g| g + 1);
        channels.push(ChannelChoice {
            location: watch.expr.clone(),
            label: watch.expr.clone(),
            group,
        });
        self.set_channels(channels);
        true
    }
}
