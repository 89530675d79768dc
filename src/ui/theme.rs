//! Colours: the egui theme and the syntax / state colours the panels share.

use egui::Color32;

pub fn apply(ctx: &egui::Context, dark: bool) {
    ctx.set_theme(if dark {
        egui::Theme::Dark
    } else {
        egui::Theme::Light
    });
    // Solid scroll bars, shown whenever there is more to see: egui's floating ones appear only
    // under the pointer, so a panel clipped at 900×600 looked complete.
    ctx.all_styles_mut(|style| style.spacing.scroll = egui::style::ScrollStyle::solid());
}

/// egui's fonts with DejaVu Sans (and Sans Mono) last in each family: the look stays egui's,
/// and the signs its fonts lack (→ ≤ ✓ ✗ ◀, used by lessons and the reference) are drawn
/// instead of empty boxes.
pub fn install_fonts(ctx: &egui::Context) {
    let mut fonts = egui::FontDefinitions::default();
    let fallbacks = [
        (
            "DejaVuSans",
            dejavu::sans::regular(),
            egui::FontFamily::Proportional,
        ),
        (
            "DejaVuSansMono",
            dejavu::sans_mono::regular(),
            egui::FontFamily::Monospace,
        ),
    ];
    for (name, bytes, family) in fallbacks {
        fonts.font_data.insert(
            name.to_owned(),
            std::sync::Arc::new(egui::FontData::from_static(bytes)),
        );
        fonts
            .families
            .entry(family)
            .or_default()
            .push(name.to_owned());
    }
    // The proportional text falls back on the mono one's signs too, and the reverse.
    for (family, other) in [
        (egui::FontFamily::Proportional, "DejaVuSansMono"),
        (egui::FontFamily::Monospace, "DejaVuSans"),
    ] {
        fonts
            .families
            .entry(family)
            .or_default()
            .push(other.to_owned());
    }
    ctx.set_fonts(fonts);
}

/// Colours that depend on the theme.
#[derive(Clone, Copy)]
pub struct Palette {
    pub mnemonic: Color32,
    pub operation: Color32,
    pub number: Color32,
    pub register: Color32,
    pub label: Color32,
    pub comment: Color32,
    pub condition: Color32,
    pub text: Color32,
    pub current_line: Color32,
    pub fault_line: Color32,
    pub breakpoint: Color32,
    pub error: Color32,
    pub written: Color32,
    pub bit_on: Color32,
    pub bit_off: Color32,
    pub dim: Color32,
}

pub fn palette(dark: bool) -> Palette {
    if dark {
        Palette {
            mnemonic: Color32::from_rgb(86, 156, 214),
            operation: Color32::from_rgb(78, 201, 176),
            number: Color32::from_rgb(181, 206, 168),
            register: Color32::from_rgb(156, 220, 254),
            label: Color32::from_rgb(220, 220, 170),
            comment: Color32::from_rgb(106, 153, 85),
            condition: Color32::from_rgb(197, 134, 192),
            text: Color32::from_rgb(212, 212, 212),
            current_line: Color32::from_rgba_unmultiplied(255, 210, 0, 40),
            fault_line: Color32::from_rgba_unmultiplied(255, 60, 60, 60),
            breakpoint: Color32::from_rgb(229, 20, 0),
            error: Color32::from_rgb(244, 71, 71),
            written: Color32::from_rgb(255, 200, 60),
            bit_on: Color32::from_rgb(60, 170, 90),
            bit_off: Color32::from_gray(60),
            dim: Color32::from_gray(130),
        }
    } else {
        Palette {
            mnemonic: Color32::from_rgb(0, 0, 255),
            operation: Color32::from_rgb(38, 127, 153),
            number: Color32::from_rgb(9, 134, 88),
            register: Color32::from_rgb(0, 16, 128),
            label: Color32::from_rgb(121, 94, 38),
            comment: Color32::from_rgb(0, 128, 0),
            condition: Color32::from_rgb(175, 0, 219),
            text: Color32::from_rgb(30, 30, 30),
            current_line: Color32::from_rgba_unmultiplied(255, 200, 0, 70),
            fault_line: Color32::from_rgba_unmultiplied(255, 0, 0, 50),
            breakpoint: Color32::from_rgb(210, 20, 0),
            error: Color32::from_rgb(205, 0, 0),
            written: Color32::from_rgb(190, 110, 0),
            bit_on: Color32::from_rgb(40, 150, 70),
            bit_off: Color32::from_gray(215),
            dim: Color32::from_gray(120),
        }
    }
}
