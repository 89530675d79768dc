//! The dockable layout: every panel is a tile of an [`egui_tiles::Tree`] that the user can
//! resize, drag into a tab stack or beside another, close (the × on its tab, or the View menu)
//! and reopen from the View menu. The tree is kept with the preferences; View -> Reset layout
//! builds the default again.
//!
//! A dialect's own panels are tiles too, named by their title; when the dialect changes,
//! [`Layout::sync_dialect_panels`] swaps them so a layout never shows another dialect's panel.

use egui_tiles::{Behavior, SimplificationOptions, TileId, Tiles, Tree, UiResponse};
use serde::{Deserialize, Serialize};

use super::panels::DialectPanel;
use super::{Command, breakpoints, code, log, plot, registers, timeline, watches};
use servoscope_core::debugger::Debugger;

/// One panel of the window.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Pane {
    Program,
    Registers,
    /// Flag words as named bits, and the selected location bit by bit.
    Bits,
    Plot,
    Timeline,
    Breakpoints,
    Watches,
    /// The execution log and log-point messages.
    Log,
    /// A dialect's own panel, by its title (SilverLode's "Queues").
    Dialect(String),
    /// The open lesson's steps and checks (shown when a lesson opens).
    Lesson,
    /// The dialect's instruction reference (F1).
    Help,
}

impl Pane {
    /// The panels every dialect has, in View-menu order.
    pub const COMMON: [Pane; 8] = [
        Pane::Program,
        Pane::Registers,
        Pane::Bits,
        Pane::Plot,
        Pane::Timeline,
        Pane::Breakpoints,
        Pane::Watches,
        Pane::Log,
    ];

    /// The titles of [`Pane::COMMON`], as preferences keep them.
    pub fn common_titles() -> Vec<String> {
        Pane::COMMON.iter().map(|p| p.title().to_string()).collect()
    }

    pub fn title(&self) -> &str {
        match self {
            Pane::Program => "Program",
            Pane::Registers => "Registers",
            Pane::Bits => "Bits",
            Pane::Plot => "Plot",
            Pane::Timeline => "Timeline",
            Pane::Breakpoints => "Breakpoints",
            Pane::Watches => "Watches",
            Pane::Log => "Log",
            Pane::Dialect(title) => title,
            Pane::Lesson => super::lesson::TITLE,
            Pane::Help => super::help::TITLE,
        }
    }

    /// The least room in which the panel is still usable (width, height, tab bar excluded).
    /// The default layout keeps every panel at least this big in a window of 900×600 or more.
    pub fn min_size(&self) -> egui::Vec2 {
        match self {
            Pane::Program => egui::vec2(260.0, 140.0),
            Pane::Registers => egui::vec2(220.0, 120.0),
            Pane::Bits => egui::vec2(220.0, 60.0),
            Pane::Plot => egui::vec2(200.0, 100.0),
            Pane::Timeline => egui::vec2(300.0, 28.0),
            Pane::Breakpoints | Pane::Watches | Pane::Log => egui::vec2(220.0, 60.0),
            Pane::Dialect(_) | Pane::Lesson | Pane::Help => egui::vec2(160.0, 80.0),
        }
    }
}

/// The panels of builds before the Breakpoints, Watches and Log panels (preferences saved by
/// them list no panels).
pub fn panes_before_debugger_panels() -> Vec<String> {
    Pane::COMMON[..5]
        .iter()
        .map(|p| p.title().to_string())
        .collect()
}

/// Dialect panels that open beside the Program panel rather than beside the plot.
const BESIDE_PROGRAM: [&str; 1] = [super::dialects::plc::ladder::TITLE];
/// Dialect panels that open as the front tab of the Bits stack (a PLC's I/O board is its bits).
const WITH_BITS: [&str; 1] = [super::dialects::plc::io_board::TITLE];

/// Below this no tile can be dragged smaller.
const MIN_TILE: f32 = 40.0;
/// The gap between tiles, and each tab bar's height.
const GAP: f32 = 4.0;
const TAB_BAR: f32 = 24.0;

const TREE_ID: &str = "servoscope_layout";

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Layout {
    pub tree: Tree<Pane>,
    /// Where each closed panel was, so View puts it back there (this run only).
    #[serde(skip)]
    pub places: Vec<(Pane, Place)>,
    /// The tab double-clicked to fill the window, until it is double-clicked again.
    #[serde(skip)]
    pub maximised: Option<TileId>,
}

/// Where a closed panel stood: beside another panel, as a tab with it or in the same row or
/// column of splits.
#[derive(Clone, Debug, PartialEq)]
pub struct Place {
    pub neighbour: Pane,
    pub as_tab: bool,
    /// In a row or column: after the neighbour's part (else before it).
    pub after: bool,
    /// Its share of the row or column, so it comes back at its size.
    pub share: Option<f32>,
}

/// The first pane in `tile`'s subtree.
fn first_pane(tiles: &Tiles<Pane>, tile: TileId) -> Option<Pane> {
    match tiles.get(tile)? {
        egui_tiles::Tile::Pane(p) => Some(p.clone()),
        egui_tiles::Tile::Container(c) => c.children().find_map(|&t| first_pane(tiles, t)),
    }
}

/// Where the pane at `tile` stands now, told by a neighbour that will outlive its closing.
pub fn place_of(tiles: &Tiles<Pane>, tile: TileId) -> Option<(Pane, Place)> {
    let pane = match tiles.get(tile)? {
        egui_tiles::Tile::Pane(p) => p.clone(),
        egui_tiles::Tile::Container(_) => return None,
    };
    // A tab container of its own (egui_tiles wraps panes so) counts as the pane's place.
    let mut me = tile;
    let mut parent = tiles.parent_of(me)?;
    while let Some(egui_tiles::Container::Tabs(tabs)) = tiles.get_container(parent) {
        if let Some(&other) = tabs.children.iter().find(|&&c| c != me) {
            let neighbour = first_pane(tiles, other)?;
            return Some((
                pane,
                Place {
                    neighbour,
                    as_tab: true,
                    after: false,
                    share: None,
                },
            ));
        }
        me = parent;
        parent = tiles.parent_of(me)?;
    }
    let Some(egui_tiles::Container::Linear(linear)) = tiles.get_container(parent) else {
        return None;
    };
    let index = linear.children.iter().position(|&c| c == me)?;
    // Prefer the part before it: the panel goes back after it.
    let (sibling, after) = match index.checked_sub(1) {
        Some(before) => (linear.children[before], true),
        None => (*linear.children.get(index + 1)?, false),
    };
    let neighbour = first_pane(tiles, sibling)?;
    Some((
        pane,
        Place {
            neighbour,
            as_tab: false,
            after,
            share: Some(linear.shares[me]),
        },
    ))
}

impl Default for Layout {
    fn default() -> Self {
        Layout::standard(&[])
    }
}

impl Layout {
    /// The default arrangement: program over the timeline and the plot (beside the dialect's
    /// panels) on the left; registers over bits (with the breakpoints, watches and log as tabs
    /// beside them) on the right.
    pub fn standard(dialect_panels: &[&str]) -> Self {
        let mut tiles = Tiles::default();
        let program = tiles.insert_pane(Pane::Program);
        // The ladder of a PLC program stands beside its mnemonics, as DirectSOFT and WindLDR
        // show both.
        let (beside_program, dialect_panels): (Vec<&str>, Vec<&str>) = dialect_panels
            .iter()
            .partition(|t| BESIDE_PROGRAM.contains(t));
        let (with_bits, dialect_panels): (Vec<&str>, Vec<&str>) =
            dialect_panels.iter().partition(|t| WITH_BITS.contains(t));
        let wide_left = !beside_program.is_empty();
        let program = match beside_program.as_slice() {
            [] => program,
            titles => {
                let mut row = vec![program];
                row.extend(
                    titles
                        .iter()
                        .map(|t| tiles.insert_pane(Pane::Dialect((*t).to_string()))),
                );
                let ids = row.clone();
                let row_id = tiles.insert_horizontal_tile(row);
                // Equal halves: the program at its minimum in a 900-px window, the ladder's
                // four cells of a typical rung in view at 1280.
                let shares: Vec<(TileId, f32)> = ids.iter().map(|&id| (id, 1.0)).collect();
                set_shares(&mut tiles, row_id, &shares);
                row_id
            }
        };
        let timeline = tiles.insert_pane(Pane::Timeline);
        let plot = tiles.insert_pane(Pane::Plot);
        let panes: Vec<TileId> = dialect_panels
            .iter()
            .map(|t| tiles.insert_pane(Pane::Dialect((*t).to_string())))
            .collect();
        // A dialect's panels stack as tabs beside the plot: the smallest window has room for
        // one panel there, not three.
        let mut lower: Vec<TileId> = match panes.len() {
            0 => Vec::new(),
            1 => panes,
            _ => vec![tiles.insert_tab_tile(panes)],
        };
        let beside_plot = lower.clone();
        lower.push(plot);
        let lower = tiles.insert_horizontal_tile(lower);
        let left = tiles.insert_vertical_tile(vec![program, timeline, lower]);
        let registers = tiles.insert_pane(Pane::Registers);
        let bits = tiles.insert_pane(Pane::Bits);
        let breakpoints = tiles.insert_pane(Pane::Breakpoints);
        let watches = tiles.insert_pane(Pane::Watches);
        let log = tiles.insert_pane(Pane::Log);
        let mut bit_tabs: Vec<TileId> = with_bits
            .iter()
            .map(|t| tiles.insert_pane(Pane::Dialect((*t).to_string())))
            .collect();
        bit_tabs.extend([bits, breakpoints, watches, log]);
        let bits = tiles.insert_tab_tile(bit_tabs);
        let right = tiles.insert_vertical_tile(vec![registers, bits]);
        let root = tiles.insert_horizontal_tile(vec![left, right]);
        set_shares(
            &mut tiles,
            left,
            &[(program, 1.4), (timeline, 0.2), (lower, 1.0)],
        );
        set_shares(&mut tiles, right, &[(registers, 3.0), (bits, 2.0)]);
        // The panels beside the plot (queue rings, stacks, tables) need the width more: the
        // plot reads at any width.
        let mut shares: Vec<(TileId, f32)> = beside_plot.into_iter().map(|t| (t, 1.0)).collect();
        shares.push((plot, 0.8));
        set_shares(&mut tiles, lower, &shares);
        // A ladder beside the program takes its room from the right column.
        let left_share = if wide_left { 3.5 } else { 3.0 };
        set_shares(&mut tiles, root, &[(left, left_share), (right, 2.0)]);
        Layout {
            tree: Tree::new(egui::Id::unique(TREE_ID), root, tiles),
            places: Vec::new(),
            maximised: None,
        }
    }

    pub fn contains(&self, pane: &Pane) -> bool {
        self.tree.tiles.find_pane(pane).is_some()
    }

    /// Drawn in the last frame (in the layout, and the active tab of its stack).
    pub fn is_shown(&self, pane: &Pane) -> bool {
        self.tree.tiles.find_pane(pane).is_some_and(|id| {
            self.tree.is_visible_in_layout(id) && self.tree.tiles.rect(id).is_some()
        })
    }

    /// Bring a pane's tab to the front.
    pub fn focus(&mut self, pane: &Pane) {
        if let Some(id) = self.tree.tiles.find_pane(pane) {
            self.tree.make_active(|tile, _| tile == id);
        }
    }

    /// Each shown pane with where it was drawn in the last frame.
    /// Where `pane` was drawn last, if it is shown.
    pub fn pane_rect(&self, pane: &Pane) -> Option<egui::Rect> {
        self.pane_rects()
            .into_iter()
            .find(|(p, _)| p == pane)
            .map(|(_, r)| r)
    }

    pub fn pane_rects(&self) -> Vec<(Pane, egui::Rect)> {
        self.tree
            .tiles
            .iter()
            .filter_map(|(&id, tile)| match tile {
                egui_tiles::Tile::Pane(pane) if self.tree.is_visible_in_layout(id) => {
                    Some((pane.clone(), self.tree.tiles.rect(id)?))
                }
                _ => None,
            })
            .collect()
    }

    /// Close a pane, or bring it back beside the others.
    pub fn set_shown(&mut self, pane: &Pane, shown: bool) {
        match (self.tree.tiles.find_pane(pane), shown) {
            (Some(id), false) => {
                self.remember_place(id);
                self.tree.remove_recursively(id);
            }
            (None, true) if self.put_back(pane) => {}
            (None, true) => {
                let id = self.tree.tiles.insert_pane(pane.clone());
                match self.tree.root() {
                    Some(root) => {
                        if let Some(egui_tiles::Tile::Container(c)) = self.tree.tiles.get_mut(root)
                        {
                            c.add_child(id);
                        }
                    }
                    None => self.tree.root = Some(id),
                }
                self.tree.make_active(|tile, _| tile == id);
            }
            _ => {}
        }
    }

    /// Where each shown pane stands now.
    pub fn current_places(&self) -> Vec<(Pane, Place)> {
        let tiles = &self.tree.tiles;
        tiles
            .tiles()
            .filter_map(|t| match t {
                egui_tiles::Tile::Pane(p) => tiles.find_pane(p),
                egui_tiles::Tile::Container(_) => None,
            })
            .filter_map(|id| place_of(tiles, id))
            .collect()
    }

    /// Note where the pane at `tile` stands, before it closes.
    pub fn remember_place(&mut self, tile: TileId) {
        if let Some((pane, place)) = place_of(&self.tree.tiles, tile) {
            self.places.retain(|(p, _)| *p != pane);
            self.places.push((pane, place));
        }
    }

    /// Put a closed pane back where it stood, if its neighbour is still shown.
    fn put_back(&mut self, pane: &Pane) -> bool {
        let Some(place) = self
            .places
            .iter()
            .find(|(p, _)| p == pane)
            .map(|(_, place)| place.clone())
        else {
            return false;
        };
        let tiles = &self.tree.tiles;
        let Some(anchor) = tiles.find_pane(&place.neighbour) else {
            return false;
        };
        // The neighbour's tab container, or the part of the row or column it is in.
        let mut part = anchor;
        let mut target = None;
        while let Some(parent) = tiles.parent_of(part) {
            match tiles.get_container(parent) {
                Some(egui_tiles::Container::Tabs(_)) if place.as_tab => {
                    target = Some((parent, None));
                    break;
                }
                Some(egui_tiles::Container::Linear(l)) if !place.as_tab => {
                    let index = l.children.iter().position(|&c| c == part).unwrap_or(0);
                    target = Some((parent, Some(index + usize::from(place.after))));
                    break;
                }
                _ => part = parent,
            }
        }
        let Some((container, index)) = target else {
            return false;
        };
        let id = self.tree.tiles.insert_pane(pane.clone());
        // In a row or column a pane stands in a tab container of its own, as egui_tiles puts
        // it: wrapped here, its share sticks.
        let part = if place.as_tab {
            id
        } else {
            self.tree.tiles.insert_tab_tile(vec![id])
        };
        match self.tree.tiles.get_mut(container) {
            Some(egui_tiles::Tile::Container(egui_tiles::Container::Tabs(tabs))) => {
                tabs.add_child(id);
            }
            Some(egui_tiles::Tile::Container(egui_tiles::Container::Linear(l))) => {
                let index = index.unwrap_or(0).min(l.children.len());
                l.children.insert(index, part);
                if let Some(share) = place.share {
                    l.shares.set_share(part, share);
                }
            }
            _ => return false,
        }
        self.tree.make_active(|tile, _| tile == id);
        true
    }

    /// Add `pane` as a tab beside `anchor` (anywhere, when `anchor` is not shown as a tab);
    /// nothing when it is already in the layout.
    pub fn add_beside(&mut self, pane: Pane, anchor: &Pane) {
        if self.contains(&pane) {
            return;
        }
        let tiles = &self.tree.tiles;
        let tabs = tiles
            .find_pane(anchor)
            .and_then(|a| tiles.parent_of(a))
            .filter(|&p| matches!(tiles.get_container(p), Some(egui_tiles::Container::Tabs(_))));
        match tabs {
            Some(tabs) => {
                let id = self.tree.tiles.insert_pane(pane);
                if let Some(egui_tiles::Tile::Container(c)) = self.tree.tiles.get_mut(tabs) {
                    c.add_child(id);
                }
            }
            None => self.set_shown(&pane, true),
        }
    }

    /// Put `pane` to the right of the Program panel (splitting its place in two).
    fn put_beside_program(&mut self, pane: Pane) {
        let id = self.tree.tiles.insert_pane(pane);
        let Some(program) = self.tree.tiles.find_pane(&Pane::Program) else {
            if let Some(egui_tiles::Tile::Container(c)) =
                self.tree.root().and_then(|r| self.tree.tiles.get_mut(r))
            {
                c.add_child(id);
            }
            return;
        };
        // Beside the Program's tab stack when it has one.
        let mut anchor = program;
        if let Some(parent) = self.tree.tiles.parent_of(program)
            && matches!(
                self.tree.tiles.get_container(parent),
                Some(egui_tiles::Container::Tabs(_))
            )
        {
            anchor = parent;
        }
        let parent = self.tree.tiles.parent_of(anchor);
        if let Some(parent) = parent
            && let Some(egui_tiles::Container::Linear(linear)) =
                self.tree.tiles.get_container(parent)
            && linear.dir == egui_tiles::LinearDir::Horizontal
        {
            if let Some(egui_tiles::Tile::Container(c)) = self.tree.tiles.get_mut(parent) {
                c.add_child(id);
            }
            return;
        }
        let row = self.tree.tiles.insert_horizontal_tile(vec![anchor, id]);
        set_shares(&mut self.tree.tiles, row, &[(anchor, 1.1), (id, 1.0)]);
        match parent {
            Some(parent) => {
                if let Some(egui_tiles::Tile::Container(c)) = self.tree.tiles.get_mut(parent) {
                    let _ = c.replace_child(anchor, row);
                    // The row takes the program's share of its column.
                    if let egui_tiles::Container::Linear(linear) = c {
                        let share = linear.shares[anchor];
                        linear.shares.set_share(row, share);
                    }
                }
            }
            None => self.tree.root = Some(row),
        }
    }

    /// Swap the dialect panels in the layout for `titles` (another dialect's). Panels of this
    /// dialect the user arranged stay where they are; another dialect's are replaced by this
    /// one's, stacked as tabs beside the plot (the smallest window has room for one there).
    pub fn sync_dialect_panels(&mut self, titles: &[&str]) {
        let present: Vec<(TileId, String)> = self
            .tree
            .tiles
            .iter()
            .filter_map(|(&id, tile)| match tile {
                egui_tiles::Tile::Pane(Pane::Dialect(t)) => Some((id, t.clone())),
                _ => None,
            })
            .collect();
        let foreign = present.iter().any(|(_, t)| !titles.contains(&t.as_str()));
        if !foreign && !present.is_empty() {
            return;
        }
        for (id, _) in present {
            self.tree.remove_recursively(id);
        }
        let (beside_program, titles): (Vec<&str>, Vec<&str>) =
            titles.iter().partition(|t| BESIDE_PROGRAM.contains(t));
        for t in beside_program {
            self.put_beside_program(Pane::Dialect(t.to_string()));
        }
        let (with_bits, titles): (Vec<&str>, Vec<&str>) =
            titles.iter().partition(|t| WITH_BITS.contains(t));
        for t in with_bits {
            let pane = Pane::Dialect(t.to_string());
            self.add_beside(pane.clone(), &Pane::Bits);
            self.focus(&pane);
        }
        if titles.is_empty() {
            return;
        }
        let ids: Vec<TileId> = titles
            .iter()
            .map(|t| self.tree.tiles.insert_pane(Pane::Dialect((*t).to_string())))
            .collect();
        let group = if ids.len() == 1 {
            ids[0]
        } else {
            self.tree.tiles.insert_tab_tile(ids)
        };
        // Beside the plot: in the container that holds it (past its own tab, if it has one).
        let tiles = &self.tree.tiles;
        let host = tiles
            .find_pane(&Pane::Plot)
            .and_then(|plot| tiles.parent_of(plot))
            .and_then(|p| match tiles.get_container(p) {
                Some(egui_tiles::Container::Tabs(_)) => tiles.parent_of(p),
                _ => Some(p),
            })
            .or(self.tree.root());
        match host.and_then(|h| self.tree.tiles.get_mut(h)) {
            Some(egui_tiles::Tile::Container(c)) => c.add_child(group),
            _ => {
                if let Some(egui_tiles::Tile::Container(c)) =
                    self.tree.root().and_then(|r| self.tree.tiles.get_mut(r))
                {
                    c.add_child(group);
                }
            }
        }
    }

    /// Hide a pane from the layout while it has nothing to show (its neighbours take the room),
    /// without closing it: it comes back by itself.
    pub fn show_when(&mut self, pane: &Pane, has_content: bool) {
        let tiles = &self.tree.tiles;
        let Some(id) = tiles.find_pane(pane) else {
            return;
        };
        // A tab of its own goes with it; in a stack with others only the pane hides.
        let target = match tiles
            .parent_of(id)
            .and_then(|p| Some((p, tiles.get_container(p)?)))
        {
            Some((parent, egui_tiles::Container::Tabs(tabs))) if tabs.children.len() == 1 => parent,
            _ => id,
        };
        let tiles = &mut self.tree.tiles;
        if has_content {
            // Its tab may have been added (or the pane hidden) after it was hidden: show both.
            for tile in [target, id] {
                if !tiles.is_visible(tile) {
                    tiles.set_visible(tile, true);
                }
            }
        } else if tiles.is_visible(target) {
            tiles.set_visible(target, false);
        }
    }

    /// Keep the timeline at `height` points (its content, plus its tab bar) when it sits in a
    /// vertical stack: its rows do not grow, so a taller window gives the room to the others.
    pub fn fit_timeline(&mut self, content_height: f32) {
        let tiles = &self.tree.tiles;
        let Some(pane) = tiles.find_pane(&Pane::Timeline) else {
            return;
        };
        // The pane sits in its tab container, which sits in the stack.
        let tabs = tiles.parent_of(pane).unwrap_or(pane);
        let Some(stack) = tiles.parent_of(tabs) else {
            return;
        };
        let Some(stack_rect) = tiles.rect(stack) else {
            return;
        };
        let Some(egui_tiles::Tile::Container(egui_tiles::Container::Linear(linear))) =
            self.tree.tiles.get_mut(stack)
        else {
            return;
        };
        if linear.dir != egui_tiles::LinearDir::Vertical || linear.children.len() < 2 {
            return;
        }
        let gaps = GAP * (linear.children.len() - 1) as f32;
        let others: f32 = linear
            .children
            .iter()
            .filter(|&&c| c != tabs)
            .map(|&c| linear.shares[c])
            .sum();
        let want = content_height + TAB_BAR + 8.0;
        let rest = stack_rect.height() - gaps - want;
        if rest > 0.0 && others > 0.0 {
            linear.shares.set_share(tabs, others * want / rest);
        }
    }

    /// Give the tab group holding `pane` this share of its row or column (0 to 1), the rest
    /// to its neighbours in proportion: the lesson's text gets room in a small window.
    pub fn give_share(&mut self, pane: &Pane, share: f32) {
        let tiles = &self.tree.tiles;
        let Some(tile) = tiles.find_pane(pane) else {
            return;
        };
        let tabs = tiles.parent_of(tile).unwrap_or(tile);
        let Some(stack) = tiles.parent_of(tabs) else {
            return;
        };
        let Some(egui_tiles::Tile::Container(egui_tiles::Container::Linear(linear))) =
            self.tree.tiles.get_mut(stack)
        else {
            return;
        };
        let others: f32 = (linear.children.iter())
            .filter(|&&c| c != tabs)
            .map(|&c| linear.shares[c])
            .sum();
        let share = share.clamp(0.05, 0.95);
        if others > 0.0 {
            linear
                .shares
                .set_share(tabs, others * share / (1.0 - share));
        }
    }

    /// A layout read from preferences, if it is usable: every tile it refers to exists.
    pub fn checked(self) -> Option<Self> {
        let tiles = &self.tree.tiles;
        let root = self.tree.root()?;
        tiles.get(root)?;
        let sound = tiles.tiles().all(|tile| match tile {
            egui_tiles::Tile::Pane(_) => true,
            egui_tiles::Tile::Container(c) => c.children().all(|child| tiles.get(*child).is_some()),
        });
        sound.then_some(self)
    }
}

fn set_shares(tiles: &mut Tiles<Pane>, container: TileId, shares: &[(TileId, f32)]) {
    if let Some(egui_tiles::Tile::Container(egui_tiles::Container::Linear(linear))) =
        tiles.get_mut(container)
    {
        for &(child, share) in shares {
            linear.shares.set_share(child, share);
        }
    }
}

/// What the panes draw from, and where they put what the user asked for.
pub struct Panes<'a> {
    pub debugger: &'a Debugger,
    pub code: &'a mut code::CodeView,
    pub registers: &'a mut registers::RegisterView,
    pub plot: &'a mut plot::PlotView,
    pub timeline: &'a mut timeline::TimelineView,
    pub breakpoints: &'a mut breakpoints::BreakpointsView,
    pub watches: &'a mut watches::WatchesView,
    pub log: &'a mut log::LogView,
    pub lesson: Option<&'a mut super::lesson::LessonView>,
    pub help: &'a mut super::help::HelpView,
    pub dialect_panels: &'a mut [Box<dyn DialectPanel>],
    pub out: &'a mut Vec<Command>,
    /// Where closed panels stood ([`Layout::places`]).
    pub places: &'a mut Vec<(Pane, Place)>,
    /// Where each shown panel stands as the frame begins ([`Layout::current_places`]).
    pub current_places: &'a [(Pane, Place)],
}

impl Behavior<Pane> for Panes<'_> {
    fn tab_title_for_pane(&mut self, pane: &Pane) -> egui::WidgetText {
        pane.title().to_string().into()
    }

    fn pane_ui(&mut self, ui: &mut egui::Ui, _tile: TileId, pane: &mut Pane) -> UiResponse {
        let rect = ui.max_rect().shrink(4.0);
        let mut ui = ui.new_child(egui::UiBuilder::new().max_rect(rect));
        ui.shrink_clip_rect(rect);
        let ui = &mut ui;
        let debugger = self.debugger;
        match pane {
            Pane::Program => code::show(ui, debugger, self.code, self.out),
            Pane::Registers => registers::show(ui, debugger, self.registers, self.out),
            Pane::Bits => registers::show_bits(ui, debugger, self.registers, self.out),
            Pane::Plot => plot::show(ui, debugger, self.plot, self.out),
            Pane::Timeline => timeline::show(ui, debugger, self.timeline, self.out),
            Pane::Breakpoints => breakpoints::show(ui, debugger, self.breakpoints, self.out),
            Pane::Watches => watches::show(ui, debugger, self.watches, self.out),
            Pane::Log => log::show(ui, debugger, self.log, self.out),
            Pane::Lesson => super::lesson::show(ui, debugger, self.lesson.as_deref_mut(), self.out),
            Pane::Help => super::help::show(ui, debugger, self.help),
            Pane::Dialect(title) => {
                let height = ui.available_height();
                match self.dialect_panels.iter_mut().find(|p| p.title() == title) {
                    Some(panel) => panel.show(ui, debugger, height, self.out),
                    None => {
                        ui.label(format!(
                            "{} has no {title} panel.",
                            debugger.dialect().display_name
                        ));
                    }
                }
            }
        }
        UiResponse::None
    }

    fn is_tab_closable(&self, _tiles: &Tiles<Pane>, _tile: TileId) -> bool {
        true
    }

    /// A double-click on a tab fills the window with it (again: back to the layout).
    fn on_tab_button(
        &mut self,
        _tiles: &mut Tiles<Pane>,
        tile: TileId,
        button_response: egui::Response,
    ) -> egui::Response {
        if button_response.double_clicked() {
            self.out.push(super::Command::ToggleMaximise(tile));
        }
        button_response
            .on_hover_text("Double-click: fill the window with this panel (again to restore)")
    }

    fn on_tab_close(&mut self, tiles: &mut Tiles<Pane>, tile: TileId) -> bool {
        // egui_tiles holds the tab's container out of `tiles` while it draws it: the place
        // was taken before the frame.
        if let Some(egui_tiles::Tile::Pane(pane)) = tiles.get(tile)
            && let Some((_, place)) = self.current_places.iter().find(|(p, _)| p == pane)
        {
            self.places.retain(|(p, _)| p != pane);
            self.places.push((pane.clone(), place.clone()));
        }
        true
    }

    /// The × keeps its size (8 px drawn) but sits 10 px from the title, not 4: a click meant
    /// for the tab no longer closes the panel.
    fn close_button_outer_size(&self) -> f32 {
        20.0
    }

    fn close_button_inner_margin(&self) -> f32 {
        6.0
    }

    fn min_size(&self) -> f32 {
        MIN_TILE
    }

    fn gap_width(&self, _style: &egui::Style) -> f32 {
        GAP
    }

    fn tab_bar_height(&self, _style: &egui::Style) -> f32 {
        TAB_BAR
    }

    fn simplification_options(&self) -> SimplificationOptions {
        SimplificationOptions {
            // Every panel keeps a tab: its title, its handle for dragging, its close button.
            all_panes_must_have_tabs: true,
            ..SimplificationOptions::default()
        }
    }
}

/// The layout inside the preferences, as RON text of its own: a layout that no longer reads
/// (written by another version, or damaged) falls back to the default without taking the
/// other preferences with it.
pub mod as_text {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::Layout;

    pub fn serialize<S: Serializer>(layout: &Option<Layout>, s: S) -> Result<S::Ok, S::Error> {
        layout
            .as_ref()
            .and_then(|l| ron::to_string(l).ok())
            .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Layout>, D::Error> {
        let text = Option::<String>::deserialize(d).unwrap_or_default();
        Ok(text.and_then(|t| ron::from_str::<Layout>(&t).ok()))
    }
}
