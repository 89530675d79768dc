//! The window's part of a session: the panel layout (which tab is in front, the sizes) and
//! where the main scroll areas were, so a reopened session looks as it was left. The core keeps
//! it as text it does not read.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::layout::Layout;

/// What a session keeps of the window.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(default)]
struct WindowState {
    /// The panel layout, as the preferences keep it.
    layout: Option<String>,
    /// The state of each noted scroll area, by its key, as egui stores it.
    scroll: BTreeMap<String, String>,
}

/// The scroll areas shown this run, by key: where egui keeps each one's state.
#[derive(Clone, Default)]
struct ScrollIds(BTreeMap<&'static str, egui::Id>);

/// Scroll states read from a session, put in place as each area is next shown.
#[derive(Clone, Default)]
struct PendingScrolls(BTreeMap<String, egui::scroll_area::State>);

/// Note that the scroll area `key` keeps its state at `id` (from its output), so sessions save
/// its position; a position read from a session for it is put back here.
pub fn note_scroll_area(ctx: &egui::Context, key: &'static str, id: egui::Id) {
    ctx.data_mut(|d| {
        d.get_temp_mut_or_default::<ScrollIds>(egui::Id::NULL)
            .0
            .insert(key, id);
        let pending = d.get_temp_mut_or_default::<PendingScrolls>(egui::Id::NULL);
        if let Some(state) = pending.0.remove(key) {
            d.insert_persisted(id, state);
        }
    });
}

/// The window's state as text for a session.
pub fn capture(ctx: &egui::Context, layout: &Layout) -> String {
    let ids = ctx.data(|d| d.get_temp::<ScrollIds>(egui::Id::NULL).unwrap_or_default());
    let scroll = (ids.0.iter())
        .filter_map(|(key, id)| {
            let state = egui::scroll_area::State::load(ctx, *id)?;
            Some((key.to_string(), ron::to_string(&state).ok()?))
        })
        .collect();
    let state = WindowState {
        layout: ron::to_string(layout).ok(),
        scroll,
    };
    ron::to_string(&state).unwrap_or_default()
}

/// Put back a session's window state: its layout (when it reads and is sound) now, its scroll
/// positions as each area is next shown. Text that does not read changes nothing.
pub fn restore(ctx: Option<&egui::Context>, text: &str, layout: &mut Layout) {
    let Ok(state) = ron::from_str::<WindowState>(text) else {
        return;
    };
    if let Some(saved) = (state.layout.as_deref())
        .and_then(|t| ron::from_str::<Layout>(t).ok())
        .and_then(Layout::checked)
    {
        *layout = saved;
    }
    let Some(ctx) = ctx else { return };
    let scrolls: BTreeMap<String, egui::scroll_area::State> = (state.scroll.into_iter())
        .filter_map(|(key, text)| Some((key, ron::from_str(&text).ok()?)))
        .collect();
    ctx.data_mut(|d| {
        d.insert_temp(egui::Id::NULL, PendingScrolls(scrolls));
    });
}
