//! The ladder diagram of a scanned PLC program, dialect-neutral and without egui: the window's
//! Ladder panel, the SVG export and the tests all read this one model.
//!
//! A dialect turns its instructions into [`Step`]s (load, and, or, the block instructions,
//! outputs, boxes); [`Ladder::build`] combines them exactly as the boolean stack does, into
//! rungs of elements joined at nodes: an element conducts from its input node(s) to its output
//! node, and coils and boxes end at the right rail. Series is "the output node of one is the
//! input node of the next", parallel is "same input node and same output node". Node 0 of every
//! rung is the left rail.
//!
//! Layout is in grid cells: a node's column is the longest path to it from the rail, every
//! contact is one cell wide, coils and boxes line up in the rung's last column; rows are given
//! greedily in program order (the first free row at or below the row its input node came in on),
//! so a parallel branch lands under the one it joins. Vertical wires join every element that
//! touches a node at that node's column.

mod build;
mod comments;
mod draw;
mod layout;
mod power;
#[cfg(test)]
mod tests;

pub use comments::{comment_of, wiring_with_comments, with_comments};
pub use draw::{RUNG_COMMENT_LINES, SVG_MARK, coil_letters, fit, svg, svg_of, value_text};
pub use power::{RungPower, RungState, power_of, rung_state};

/// A node of a rung; [`RAIL`] is the left power rail.
/// A warning for each `OUT`-style coil that drives a bit another rung's `OUT` already drives:
/// the last rung wins every scan and the earlier one seems dead, which DirectSOFT's program
/// check and WindLDR's both warn of. SET/RST pairs, pulses and OROUT may share a bit, and so
/// may OUTs in different stages or subroutines (only the active stage's rungs are scanned: the
/// same lamp is commonly driven by each stage that needs it, as in `push_on_off.dl205`).
pub fn duplicate_coils(ladder: &Ladder) -> Vec<crate::machine::Diagnostic> {
    let mut first: std::collections::HashMap<(usize, &str), (usize, usize)> = Default::default();
    let mut out = Vec::new();
    let mut scope = 0;
    for (r, rung) in ladder.rungs.iter().enumerate() {
        for e in &rung.elements {
            if e.symbol == Symbol::Box
                && ["SG", "ISG", "SBR"].contains(&e.operand.to_ascii_uppercase().as_str())
            {
                scope += 1;
            }
            if !matches!(e.symbol, Symbol::Coil(CoilKind::Out | CoilKind::OutNot)) {
                continue;
            }
            match first.get(&(scope, e.operand.as_str())) {
                Some(&(rung_at, line)) if rung_at != r => {
                    out.push(crate::machine::Diagnostic {
                        severity: crate::machine::Severity::Warning,
                        line: e.line,
                        col: 1,
                        len: 1,
                        message: format!(
                            "{} is already an output coil on line {line}: the last rung scanned \
                             wins, so line {line} seems to do nothing (drive {} from one rung, \
                             or use SET/RST)",
                            e.operand, e.operand
                        ),
                    });
                }
                Some(_) => {}
                None => {
                    first.insert((scope, e.operand.as_str()), (r, e.line));
                }
            }
        }
    }
    out
}

pub type NodeId = u32;
pub const RAIL: NodeId = 0;

/// Which change an edge element reacts to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    Rising,
    Falling,
}

/// What kind of coil an output is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoilKind {
    /// `-( )-`
    Out,
    /// `-(/)-`: the bit takes the inverse of the rung (OpenNet OUTN).
    OutNot,
    /// `-(S)-`
    Set,
    /// `-(R)-`
    Reset,
    /// `-(PD)-`: on for one scan at the rung's rise.
    Pulse,
    /// `-(OR)-`: DL205 OROUT.
    OrOut,
    /// `-(JMP)-`: DL205's stage jump, drawn as DirectSOFT draws it, a coil naming the stage.
    Jump,
}

/// How an element is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symbol {
    /// `-| |-` (normally open) or `-|/|-` (normally closed); with an edge, `-|↑|-` / `-|↓|-`.
    Contact {
        closed: bool,
        edge: Option<EdgeKind>,
    },
    /// A comparison that conducts while it holds (`V2000 >= K10`).
    Compare,
    /// Inverts the power of everything before it (DL205 NOT).
    Invert,
    /// Passes one scan's pulse when the power before it changes (OpenNet SOTU/SOTD).
    PowerEdge(EdgeKind),
    Coil(CoilKind),
    /// Everything else: math, moves, timers, counters, stages, jumps.
    Box,
}

impl Symbol {
    /// Ends at the right rail (a coil or a box).
    pub fn is_terminal(self) -> bool {
        matches!(self, Symbol::Coil(_) | Symbol::Box)
    }
}

/// One drawn element of a rung.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Element {
    pub symbol: Symbol,
    /// Index of its instruction, and its 1-based source line.
    pub instr: usize,
    pub line: usize,
    /// The bit it reads or writes (`X1`, `Q0`), or for a box its mnemonic (`TMR`).
    pub operand: String,
    /// What the diagram writes on it: the bit's name, the comparison, the box's text.
    pub text: String,
    /// Locations a box shows live, by name (`TA1`, `V2000`).
    pub values: Vec<String>,
    /// Where each input comes from (one per leg for a box with several: count and reset).
    pub from: Vec<NodeId>,
    /// Its output node; None for coils and boxes (they end at the right rail).
    pub to: Option<NodeId>,
    /// Layout: the cell of its symbol (for a box with legs, the top one) and its height in rows.
    pub col: u16,
    pub row: u16,
    pub height: u16,
    /// The column its input wire starts in (a coil's wire runs from there to the last column).
    pub from_col: u16,
    /// The row each input enters at (a box's legs each at their own network's row).
    pub leg_rows: Vec<u16>,
    /// The trailing comment of its line.
    pub comment: String,
}

/// A vertical wire at a node: column boundary `col`, rows `top..=bottom`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Vertical {
    pub node: NodeId,
    pub col: u16,
    pub top: u16,
    pub bottom: u16,
}

/// A horizontal wire filling cells `from_col..to_col` of `row` with the power of `node`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Filler {
    pub node: NodeId,
    pub row: u16,
    pub from_col: u16,
    pub to_col: u16,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Rung {
    pub elements: Vec<Element>,
    pub nodes: u32,
    /// Column of each node.
    pub node_col: Vec<u16>,
    /// The column coils and boxes stand in; the rung is `last_col + 1` cells wide.
    pub last_col: u16,
    pub rows: u16,
    pub verticals: Vec<Vertical>,
    pub fillers: Vec<Filler>,
    /// The comment lines right above the rung's first instruction.
    pub comment: String,
    /// Why the rung is not drawn (wider or taller than the ladder draws): what the panel and
    /// the SVG show in its place.
    pub oversized: Option<String>,
}

/// A program's diagram laid out on first use: assembling wires the rungs, and only what draws
/// them (the panel, the SVG) pays for the layout. Two programs compare equal whether or not
/// either was drawn yet.
#[derive(Clone, Debug, Default)]
pub struct LaidOut(std::sync::OnceLock<std::sync::Arc<Ladder>>);

impl LaidOut {
    /// `wired` laid out, the first time; the same diagram after that.
    pub fn of(&self, wired: &Ladder) -> std::sync::Arc<Ladder> {
        self.0
            .get_or_init(|| {
                let mut ladder = wired.clone();
                ladder.lay_out();
                std::sync::Arc::new(ladder)
            })
            .clone()
    }
}

impl PartialEq for LaidOut {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for LaidOut {}

/// The widest rung the ladder draws, in cells (about 56,000 pixels at 110 a cell).
pub const MAX_RUNG_COLUMNS: usize = 512;
/// The tallest rung the ladder draws, in rows.
pub const MAX_RUNG_ROWS: usize = 1024;

impl Rung {
    /// The first and last instruction of the rung.
    pub fn instrs(&self) -> (usize, usize) {
        let first = self.elements.iter().map(|e| e.instr).min().unwrap_or(0);
        let last = self.elements.iter().map(|e| e.instr).max().unwrap_or(0);
        (first, last)
    }

    pub fn first_line(&self) -> usize {
        self.elements.iter().map(|e| e.line).min().unwrap_or(0)
    }

    /// Elements whose output node is `node`.
    pub fn into_node(&self, node: NodeId) -> impl Iterator<Item = &Element> {
        self.elements.iter().filter(move |e| e.to == Some(node))
    }

    /// The elements connected directly before `e` (None in the list: the left rail).
    pub fn before(&self, e: &Element) -> Vec<Option<&Element>> {
        let mut out = Vec::new();
        for &n in &e.from {
            if n == RAIL {
                out.push(None);
            }
            out.extend(self.into_node(n).map(Some));
        }
        out
    }
}

/// The diagram of a whole program.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Ladder {
    pub rungs: Vec<Rung>,
    /// The widest rung's last column: coils and boxes of every rung are drawn there.
    pub last_col: u16,
}

/// One instruction as the boolean stack sees it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step {
    /// Starts a block (STR, LOD, a compare that starts one); after an output, a new rung.
    Load(Element),
    And(Element),
    Or(Element),
    /// ANDSTR/ANDLOD, ORSTR/ORLOD: the two blocks on top in series / in parallel.
    AndBlock,
    OrBlock,
    /// An element in series with the current block that is not a contact (NOT, SOTU).
    Series(Element),
    /// OpenNet's branch stack: BPS saves the point, BRD goes back to it, BPP goes back and
    /// forgets it.
    Push,
    Read,
    Pop,
    /// A coil or box on the current block's power (other outputs may follow on the same).
    Output(Element),
    /// A box with this many legs: the top `legs - 1` blocks on the stack and the current one,
    /// in program order (count and reset; up, down and reset).
    Boxed(Element, usize),
    /// An instruction that stands alone as its own rung (END, a label, a stage, MCR).
    Alone(Element),
    /// Takes no part (NOP).
    Skip,
}

impl Element {
    /// An element before the builder wires it.
    pub fn new(symbol: Symbol, instr: usize, line: usize, operand: impl Into<String>) -> Self {
        let operand = operand.into();
        Element {
            symbol,
            instr,
            line,
            text: operand.clone(),
            operand,
            values: Vec::new(),
            from: Vec::new(),
            to: None,
            col: 0,
            row: 0,
            height: 1,
            from_col: 0,
            leg_rows: Vec::new(),
            comment: String::new(),
        }
    }

    pub fn text(mut self, text: impl Into<String>) -> Self {
        self.text = text.into();
        self
    }

    pub fn values(mut self, values: Vec<String>) -> Self {
        self.values = values;
        self
    }
}

impl Ladder {
    /// The rung holding instruction `instr`.
    pub fn rung_of(&self, instr: usize) -> Option<usize> {
        self.rungs
            .iter()
            .position(|r| r.elements.iter().any(|e| e.instr == instr))
    }
}
