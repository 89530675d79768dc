//! Inputs as push buttons: an input the user makes a push button is on from the press to the
//! release (a start button held for a moment), where a switch toggles on each click. The I/O
//! board and the input bar share the choice (egui's memory, for this run of the window).

use servoscope_core::debugger::Action;
use servoscope_core::machine::Loc;

use super::Command;

/// Inputs the user made push buttons (on while held), and the one held now: kept in egui's
/// memory so the I/O board and the input bar share them.
#[derive(Clone, Default)]
struct PushButtons {
    buttons: std::collections::BTreeSet<Loc>,
    held: Option<Loc>,
}

fn push_buttons(ctx: &egui::Context) -> PushButtons {
    ctx.data(|d| {
        d.get_temp::<PushButtons>(egui::Id::NULL)
            .unwrap_or_default()
    })
}

/// Whether `loc` is a push button (on while held) rather than a switch.
pub fn is_push_button(ctx: &egui::Context, loc: Loc) -> bool {
    push_buttons(ctx).buttons.contains(&loc)
}

/// Make `loc` a push button or a switch again.
pub fn set_push_button(ctx: &egui::Context, loc: Loc, push: bool) {
    ctx.data_mut(|d| {
        let p = d.get_temp_mut_or_default::<PushButtons>(egui::Id::NULL);
        if push {
            p.buttons.insert(loc);
        } else {
            p.buttons.remove(&loc);
        }
    });
}

/// An input's click: a switch toggles; a push button is on from the press to the release.
pub fn switch_input(response: &egui::Response, loc: Loc, on: bool, out: &mut Vec<Command>) {
    let ctx = &response.ctx;
    if !is_push_button(ctx, loc) {
        if response.clicked() {
            out.push(Command::Debug(Action::SetInput(loc, !on)));
        }
        return;
    }
    let down = response.is_pointer_button_down_on();
    let held = push_buttons(ctx).held == Some(loc);
    // Released anywhere: a pointer that slides off the button while held still lets go.
    let released = !ctx.input(|i| i.pointer.primary_down());
    if down && !held && !released {
        ctx.data_mut(|d| {
            d.get_temp_mut_or_default::<PushButtons>(egui::Id::NULL)
                .held = Some(loc)
        });
        if !on {
            out.push(Command::Debug(Action::SetInput(loc, true)));
        }
    } else if released && held {
        ctx.data_mut(|d| {
            d.get_temp_mut_or_default::<PushButtons>(egui::Id::NULL)
                .held = None
        });
        if on {
            out.push(Command::Debug(Action::SetInput(loc, false)));
        }
    }
}

/// The context-menu item that turns an input into a push button or back.
pub fn push_button_item(ui: &mut egui::Ui, loc: Loc) {
    let push = is_push_button(ui.ctx(), loc);
    let text = if push {
        "Make it a switch (a click toggles)"
    } else {
        "Make it a push button (on while held)"
    };
    if ui.button(text).clicked() {
        set_push_button(ui.ctx(), loc, !push);
        ui.close();
    }
}
