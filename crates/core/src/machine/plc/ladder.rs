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

use std::fmt::Write as _;

/// A node of a rung; [`RAIL`] is the left power rail.
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
}

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

#[derive(Clone, Copy, Debug)]
struct Block {
    start: NodeId,
    end: NodeId,
}

/// The rung under construction.
#[derive(Default)]
struct Builder {
    elements: Vec<Element>,
    parent: Vec<NodeId>,
    cur: Option<Block>,
    stack: Vec<Block>,
    points: Vec<NodeId>,
    has_output: bool,
}

impl Builder {
    fn new() -> Self {
        Builder {
            parent: vec![RAIL],
            ..Default::default()
        }
    }

    fn node(&mut self) -> NodeId {
        self.parent.push(self.parent.len() as NodeId);
        (self.parent.len() - 1) as NodeId
    }

    fn find(&mut self, mut n: NodeId) -> NodeId {
        while self.parent[n as usize] != n {
            let up = self.parent[self.parent[n as usize] as usize];
            self.parent[n as usize] = up;
            n = up;
        }
        n
    }

    /// Make `a` and `b` one node (the rail stays the rail).
    fn join(&mut self, a: NodeId, b: NodeId) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            let (keep, gone) = if a < b { (a, b) } else { (b, a) };
            self.parent[gone as usize] = keep;
        }
    }

    fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    fn load(&mut self, mut e: Element) {
        if let Some(b) = self.cur.take() {
            self.stack.push(b);
        }
        let (start, end) = (self.node(), self.node());
        e.from = vec![start];
        e.to = Some(end);
        self.elements.push(e);
        self.cur = Some(Block { start, end });
    }

    /// The current block, or a fresh one at the rail for an element with nothing before it.
    fn current(&mut self) -> Block {
        *self.cur.get_or_insert(Block {
            start: RAIL,
            end: RAIL,
        })
    }

    fn series(&mut self, mut e: Element) {
        let b = self.current();
        let end = self.node();
        e.from = vec![b.end];
        e.to = Some(end);
        self.elements.push(e);
        self.cur = Some(Block {
            start: b.start,
            end,
        });
    }

    fn parallel(&mut self, mut e: Element) {
        let b = self.current();
        if b.start == b.end {
            // Nothing to be parallel to: a contact in series from the rail.
            return self.series(e);
        }
        e.from = vec![b.start];
        e.to = Some(b.end);
        self.elements.push(e);
    }

    fn and_block(&mut self) {
        let (Some(b), Some(a)) = (self.cur, self.stack.pop()) else {
            return;
        };
        self.join(b.start, a.end);
        self.cur = Some(Block {
            start: a.start,
            end: b.end,
        });
    }

    fn or_block(&mut self) {
        let (Some(b), Some(a)) = (self.cur, self.stack.pop()) else {
            return;
        };
        self.join(b.start, a.start);
        self.join(b.end, a.end);
        self.cur = Some(a);
    }

    /// Roots every open block at the rail: an output takes the rung's power from there.
    fn root(&mut self) {
        if !self.has_output {
            let starts: Vec<NodeId> = self
                .stack
                .iter()
                .chain(self.cur.as_ref())
                .map(|b| b.start)
                .collect();
            for s in starts {
                self.join(s, RAIL);
            }
        }
        self.has_output = true;
    }

    fn output(&mut self, mut e: Element) {
        let b = self.current();
        self.root();
        e.from = vec![b.end];
        e.to = None;
        self.elements.push(e);
    }

    fn boxed(&mut self, mut e: Element, legs: usize) {
        let b = self.current();
        self.root();
        let mut ends = vec![b.end];
        for _ in 1..legs.max(1) {
            match self.stack.pop() {
                Some(a) => ends.insert(0, a.end),
                None => break,
            }
        }
        e.from = ends;
        e.to = None;
        self.elements.push(e);
    }

    /// The finished rung, with nodes numbered in order of first use and laid out.
    fn finish(mut self, rungs: &mut Vec<Rung>) {
        if self.is_empty() {
            return;
        }
        self.root();
        let mut number = vec![u32::MAX; self.parent.len()];
        number[RAIL as usize] = RAIL;
        let mut next = 1;
        let mut elements = std::mem::take(&mut self.elements);
        for e in &mut elements {
            for n in e.from.iter_mut().chain(e.to.as_mut()) {
                let root = self.find(*n) as usize;
                if number[root] == u32::MAX {
                    number[root] = next;
                    next += 1;
                }
                *n = number[root];
            }
        }
        let mut rung = Rung {
            elements,
            nodes: next,
            ..Default::default()
        };
        layout(&mut rung);
        rungs.push(rung);
    }
}

/// Columns, rows, fillers and verticals of a wired rung.
fn layout(rung: &mut Rung) {
    let n = rung.nodes as usize;
    // Longest path from the rail; the graph is acyclic (every element ends at a newer node),
    // so as many passes as elements settle it.
    let mut col = vec![0u16; n];
    for _ in 0..=rung.elements.len() {
        let mut changed = false;
        for e in &rung.elements {
            if let (Some(to), Some(&from)) = (e.to, e.from.first()) {
                let want = col[from as usize].saturating_add(1);
                if col[to as usize] < want {
                    col[to as usize] = want;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    let last_col = rung
        .elements
        .iter()
        .filter(|e| e.to.is_none())
        .flat_map(|e| e.from.iter().map(|&f| col[f as usize]))
        .chain(col.iter().copied())
        .max()
        .unwrap_or(0);
    // Rows: cells taken, per row.
    let mut taken: Vec<Vec<bool>> = Vec::new();
    let width = usize::from(last_col) + 1;
    let mut node_row: Vec<Option<u16>> = vec![None; n];
    node_row[RAIL as usize] = Some(0);
    let fits = |taken: &Vec<Vec<bool>>, row: usize, a: usize, b: usize| {
        taken.get(row).is_none_or(|r| r[a..b].iter().all(|t| !t))
    };
    let mut fillers = Vec::new();
    for e in &mut rung.elements {
        let first = e.from.first().copied().unwrap_or(RAIL);
        let a = usize::from(col[first as usize]);
        let (b, height) = match e.to {
            Some(to) => (usize::from(col[to as usize]).max(a + 1), 1),
            None => (width, e.from.len().max(1)),
        };
        let want = usize::from(node_row[first as usize].unwrap_or(0));
        // A box's legs enter at the rows their networks came in on, where those are below.
        let legs: Vec<usize> = e
            .from
            .iter()
            .enumerate()
            .map(|(k, &f)| node_row[f as usize].map_or(want + k, usize::from))
            .collect();
        let height = if e.to.is_none() {
            let spread = legs.iter().max().copied().unwrap_or(want) + 1;
            height.max(spread.saturating_sub(want)).max(1)
        } else {
            height
        };
        let mut row = want;
        while !(0..height).all(|k| fits(&taken, row + k, a, b)) {
            row += 1;
        }
        while taken.len() < row + height {
            taken.push(vec![false; width]);
        }
        for r in taken.iter_mut().skip(row).take(height) {
            r[a..b].iter_mut().for_each(|t| *t = true);
        }
        e.leg_rows = legs
            .iter()
            .enumerate()
            .map(|(k, &l)| (l + row - want).max(row + k.min(height - 1)) as u16)
            .collect();
        if e.leg_rows.is_empty() {
            e.leg_rows.push(row as u16);
        }
        e.row = row as u16;
        e.height = height as u16;
        e.from_col = a as u16;
        e.col = if e.to.is_some() { a as u16 } else { last_col };
        node_row[first as usize].get_or_insert(row as u16);
        if let Some(to) = e.to {
            node_row[to as usize].get_or_insert(row as u16);
        }
        if e.to.is_some() && b > a + 1 {
            fillers.push(Filler {
                node: e.to.unwrap_or(RAIL),
                row: row as u16,
                from_col: (a + 1) as u16,
                to_col: b as u16,
            });
        }
    }
    // Verticals: every point where an element meets a node, per node.
    let mut touch: Vec<Vec<u16>> = vec![Vec::new(); n];
    for e in &rung.elements {
        for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
            touch[f as usize].push(row);
        }
        if let Some(to) = e.to {
            touch[to as usize].push(e.row);
        }
    }
    let mut verticals = Vec::new();
    for (node, rows) in touch.iter().enumerate() {
        if node == RAIL as usize {
            continue;
        }
        if let (Some(&top), Some(&bottom)) = (rows.iter().min(), rows.iter().max())
            && top != bottom
        {
            verticals.push(Vertical {
                node: node as NodeId,
                col: col[node],
                top,
                bottom,
            });
        }
    }
    rung.rows = taken.len().max(1) as u16;
    rung.node_col = col;
    rung.last_col = last_col;
    rung.fillers = fillers;
    rung.verticals = verticals;
}

impl Ladder {
    /// The diagram of a program given as boolean-stack steps in program order.
    pub fn build(steps: impl IntoIterator<Item = Step>) -> Ladder {
        let mut rungs = Vec::new();
        let mut b = Builder::new();
        for step in steps {
            match step {
                Step::Load(e) => {
                    if b.has_output {
                        std::mem::replace(&mut b, Builder::new()).finish(&mut rungs);
                    }
                    b.load(e);
                }
                Step::And(e) | Step::Series(e) => b.series(e),
                Step::Or(e) => b.parallel(e),
                Step::AndBlock => b.and_block(),
                Step::OrBlock => b.or_block(),
                Step::Push => {
                    let end = b.current().end;
                    b.points.push(end);
                }
                Step::Read | Step::Pop => {
                    let point = if step == Step::Read {
                        b.points.last().copied()
                    } else {
                        b.points.pop()
                    };
                    if let (Some(p), Some(cur)) = (point, b.cur.as_mut()) {
                        cur.end = p;
                    }
                }
                Step::Output(e) => b.output(e),
                Step::Boxed(e, legs) => b.boxed(e, legs),
                Step::Alone(e) => {
                    std::mem::replace(&mut b, Builder::new()).finish(&mut rungs);
                    // No rung condition: nothing feeds it.
                    b.elements.push(e);
                    std::mem::replace(&mut b, Builder::new()).finish(&mut rungs);
                    b.has_output = true;
                }
                Step::Skip => {}
            }
        }
        b.finish(&mut rungs);
        let last_col = rungs.iter().map(|r| r.last_col).max().unwrap_or(0);
        Ladder { rungs, last_col }
    }

    /// Attach each element's trailing comment and each rung's comment lines from the source;
    /// `comment_of(line)` is the comment part of one line ("" when none).
    pub fn attach_comments(&mut self, source: &str, comment_of: impl Fn(&str) -> String) {
        let lines: Vec<&str> = source.lines().collect();
        let comment = |line: usize| -> String {
            lines
                .get(line.wrapping_sub(1))
                .map(|l| comment_of(l))
                .unwrap_or_default()
        };
        let mut taken = 0usize;
        for rung in &mut self.rungs {
            for e in &mut rung.elements {
                e.comment = comment(e.line);
            }
            // Comment-only lines right above the rung, after the previous rung's last line.
            let first = rung.first_line();
            let mut above = Vec::new();
            let mut l = first.saturating_sub(1);
            while l > taken {
                let text = lines.get(l - 1).map_or("", |s| s.trim());
                let c = comment(l);
                // A comment-only line: before its comment there is only the marker.
                let only = text
                    .strip_suffix(c.as_str())
                    .is_some_and(|code| !code.chars().any(char::is_alphanumeric));
                if c.is_empty() || !only {
                    break;
                }
                above.push(c);
                l -= 1;
            }
            above.reverse();
            rung.comment = above.join("\n");
            taken = rung
                .elements
                .iter()
                .map(|e| e.line)
                .max()
                .unwrap_or(taken)
                .max(taken);
        }
    }

    /// The rung holding instruction `instr`.
    pub fn rung_of(&self, instr: usize) -> Option<usize> {
        self.rungs
            .iter()
            .position(|r| r.elements.iter().any(|e| e.instr == instr))
    }
}

/// The comment part of one source line as the dialect's highlighter classes it, without its
/// marker (`//`, `;`): what the diagram writes under an element or above a rung.
pub fn comment_of(
    classify: fn(&str) -> Vec<crate::machine::dialect::TokenClass>,
    line: &str,
) -> String {
    let classes = classify(line);
    let text: String = line
        .chars()
        .zip(classes.iter().chain(std::iter::repeat(
            &crate::machine::dialect::TokenClass::Plain,
        )))
        .filter(|(_, c)| **c == crate::machine::dialect::TokenClass::Comment)
        .map(|(ch, _)| ch)
        .collect();
    text.trim()
        .trim_start_matches("//")
        .trim_start_matches(';')
        .trim()
        .to_string()
}

/// The machine's diagram with the comments of `source` attached (None: not a ladder dialect).
pub fn with_comments(
    m: &dyn crate::machine::MachineView,
    source: &str,
    classify: fn(&str) -> Vec<crate::machine::dialect::TokenClass>,
) -> Option<Ladder> {
    let mut ladder = (*m.as_plc()?.ladder()).clone();
    ladder.attach_comments(source, |line| comment_of(classify, line));
    Some(ladder)
}

/// A live value a box shows, in the location's own reading: `TA1 = 29` (BCD on a DL205).
pub fn value_text(m: &dyn crate::machine::MachineView, name: &str) -> String {
    match m.find(name).and_then(|loc| Some((loc, m.info(loc)?))) {
        Some((loc, info)) => format!("{name} = {}", info.reading().show(m.read(loc), info.width)),
        None => name.to_string(),
    }
}

/// The whole diagram of `m` as SVG with its power flow now.
pub fn svg_of(m: &dyn crate::machine::MachineView, ladder: &Ladder, title: &str) -> String {
    let power = power_of(ladder, m);
    let forced = |name: &str| m.find(name).and_then(|loc| m.forced(loc));
    svg(ladder, &power, title, &|name| value_text(m, name), &forced)
}

/// Where a rung is in the scan now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RungState {
    /// Evaluated in this scan (or the previous one, between scans).
    Done,
    /// Later in the scan than where the machine stands.
    NotYet,
    /// Not run this scan: jumped over, an inactive stage, a subroutine not called.
    NotRun,
    /// In a master-control area that is off.
    MasterOff,
}

/// The live power of one rung.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RungPower {
    pub state: RungState,
    /// Power at each node.
    pub node: Vec<bool>,
    /// Per element: a contact conducts, a coil or box has power at its (first) input.
    pub element: Vec<bool>,
}

impl RungPower {
    /// The power of `rung` when `conducts(instr)` says which contacts conduct.
    pub fn of(rung: &Rung, state: RungState, conducts: impl Fn(usize) -> bool) -> RungPower {
        let mut node = vec![false; rung.nodes as usize];
        // Only a rung this scan evaluated has power: one not reached yet, jumped over or in an
        // MCS area that is off shows its contacts' bits, its coils and boxes no power.
        node[RAIL as usize] = state == RungState::Done;
        let mut order: Vec<usize> = (0..rung.elements.len()).collect();
        order.sort_by_key(|&i| {
            let e = &rung.elements[i];
            e.from
                .first()
                .map_or(0, |&f| rung.node_col.get(f as usize).copied().unwrap_or(0))
        });
        let mut element = vec![false; rung.elements.len()];
        for i in order {
            let e = &rung.elements[i];
            let input = e
                .from
                .first()
                .is_some_and(|&f| node.get(f as usize).copied().unwrap_or(false));
            let (shown, out) = match e.symbol {
                Symbol::Contact { .. } | Symbol::Compare => {
                    let c = conducts(e.instr);
                    (c, input && c)
                }
                Symbol::Invert => (!input, !input),
                Symbol::PowerEdge(_) => {
                    let c = conducts(e.instr);
                    (c, c)
                }
                Symbol::Coil(_) | Symbol::Box => (input, false),
            };
            element[i] = shown;
            if let Some(to) = e.to
                && out
                && let Some(n) = node.get_mut(to as usize)
            {
                *n = true;
            }
        }
        RungPower {
            state,
            node,
            element,
        }
    }
}

/// The live state of a diagram: each rung's power.
pub fn power_of(ladder: &Ladder, m: &dyn crate::machine::MachineView) -> Vec<RungPower> {
    let Some(plc) = m.as_plc() else {
        return Vec::new();
    };
    let lines = plc.line_power();
    let now = m.pos();
    let pc = m.pc_line();
    ladder
        .rungs
        .iter()
        .map(|rung| {
            let first = rung.first_line();
            let state = match lines.iter().find(|(l, _)| *l == first).map(|(_, p)| *p) {
                Some(crate::machine::LinePower::NotRun) => RungState::NotRun,
                Some(crate::machine::LinePower::MasterOff) => RungState::MasterOff,
                _ if now.step > 0 && pc.is_some_and(|pc| first >= pc) => RungState::NotYet,
                _ => RungState::Done,
            };
            RungPower::of(rung, state, |i| plc.ladder_conducts(i))
        })
        .collect()
}

/// Cell size of the SVG drawing, in px.
const CELL_W: u32 = 110;
const CELL_H: u32 = 76;
const RUNG_GAP: u32 = 26;
/// Lines of a rung's comment a drawing shows (a file's opening paragraph can be long).
pub const RUNG_COMMENT_LINES: usize = 3;

fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// Stroke attributes of a wire or symbol, lit or not (attributes, not CSS: every SVG reader
/// honours them).
fn stroke(lit: bool) -> &'static str {
    if lit {
        r##"stroke="#1a9c3a" stroke-width="3""##
    } else {
        r##"stroke="#555555" stroke-width="2""##
    }
}

/// `text` cut to `max` characters with an ellipsis.
pub fn fit(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let mut t: String = text.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// The drawn symbol of a coil: `( )`, `(S)`.
pub fn coil_letters(kind: CoilKind) -> &'static str {
    match kind {
        CoilKind::Out => " ",
        CoilKind::OutNot => "/",
        CoilKind::Set => "S",
        CoilKind::Reset => "R",
        CoilKind::Pulse => "PD",
        CoilKind::OrOut => "OR",
        CoilKind::Jump => "JMP",
    }
}

/// The diagram as a standalone SVG document with the power flow of `power` (one per rung);
/// `values(name)` gives the text a box shows for a live value (`TA1 = 29`). Every element is a
/// `<g class="element">` with `data-line`, `data-operand` and `data-powered`; every rung a
/// `<g class="rung" data-rung="K">`.
pub fn svg(
    ladder: &Ladder,
    power: &[RungPower],
    title: &str,
    values: &dyn Fn(&str) -> String,
    forced: &dyn Fn(&str) -> Option<bool>,
) -> String {
    let cols = u32::from(ladder.last_col) + 1;
    let left = 40u32;
    // Room right of the right rail for a rung's state.
    let width = left * 2 + cols * CELL_W + 120;
    let mut y = 50u32;
    let mut body = String::new();
    for (k, rung) in ladder.rungs.iter().enumerate() {
        let pw = power.get(k);
        let comment: Vec<&str> = rung.comment.lines().take(RUNG_COMMENT_LINES).collect();
        let comment_lines = comment.len() as u32;
        let top = y + comment_lines * 14 + if comment_lines > 0 { 8 } else { 0 };
        let height = u32::from(rung.rows) * CELL_H;
        let _ = writeln!(
            body,
            r#"<g class="rung" data-rung="{k}" data-line="{}">"#,
            rung.first_line()
        );
        for (i, line) in comment.iter().enumerate() {
            let _ = writeln!(
                body,
                r##"<text class="comment" x="{left}" y="{}" fill="#2a7a2a" font-style="italic">{}</text>"##,
                y + 12 + i as u32 * 14,
                escape(&fit(line, (width as usize - left as usize) / 6))
            );
        }
        let on = |node: NodeId| pw.is_some_and(|p| p.node.get(node as usize) == Some(&true));
        let wire = |body: &mut String, x1: u32, y1: u32, x2: u32, y2: u32, lit: bool| {
            let _ = writeln!(
                body,
                r#"<line class="wire{}" x1="{x1}" y1="{y1}" x2="{x2}" y2="{y2}" {}/>"#,
                if lit { " on" } else { "" },
                stroke(lit)
            );
        };
        let x_of = |c: u32| left + c * CELL_W;
        let y_of = |r: u32| top + r * CELL_H + CELL_H / 2;
        let state = pw.map_or(RungState::Done, |p| p.state);
        // Rails.
        wire(
            &mut body,
            left,
            top,
            left,
            top + height,
            state == RungState::Done,
        );
        let right = x_of(cols);
        let note = match state {
            RungState::Done => None,
            RungState::NotYet => Some("not yet this scan"),
            RungState::NotRun => Some("not run this scan"),
            RungState::MasterOff => Some("MC off: outputs off"),
        };
        if let Some(note) = note {
            let _ = writeln!(
                body,
                r##"<text class="state" x="{}" y="{}" fill="#888888" font-style="italic">{note}</text>"##,
                right + 6,
                top + 14
            );
        }
        wire(&mut body, right, top, right, top + height, false);
        for f in &rung.fillers {
            wire(
                &mut body,
                x_of(u32::from(f.from_col)),
                y_of(u32::from(f.row)),
                x_of(u32::from(f.to_col)),
                y_of(u32::from(f.row)),
                on(f.node),
            );
        }
        for v in &rung.verticals {
            wire(
                &mut body,
                x_of(u32::from(v.col)),
                y_of(u32::from(v.top)),
                x_of(u32::from(v.col)),
                y_of(u32::from(v.bottom)),
                on(v.node),
            );
        }
        for (i, e) in rung.elements.iter().enumerate() {
            let powered = pw.is_some_and(|p| p.element.get(i) == Some(&true));
            let col = if e.to.is_none() {
                cols - 1
            } else {
                u32::from(e.col)
            };
            let (x, yc) = (x_of(col), y_of(u32::from(e.row)));
            let force = forced(&e.operand);
            let _ = writeln!(
                body,
                r#"<g class="element{}" data-line="{}" data-operand="{}" data-powered="{}"{}>"#,
                if powered { " on" } else { "" },
                e.line,
                escape(&e.operand),
                u8::from(powered),
                match force {
                    Some(on) => format!(r#" data-forced="{}""#, u8::from(on)),
                    None => String::new(),
                }
            );
            if let Some(on) = force {
                let _ = writeln!(
                    body,
                    r##"<rect x="{}" y="{}" width="20" height="13" rx="3" fill="#e67814"/><text x="{}" y="{}" fill="#ffffff" font-size="9" text-anchor="middle">F{}</text>"##,
                    x + CELL_W / 2 + 14,
                    yc + 8,
                    x + CELL_W / 2 + 24,
                    yc + 18,
                    u8::from(on)
                );
            }
            let input_lit = e.from.first().is_some_and(|&f| on(f));
            // A coil's or box's input wires run from their nodes to its column.
            if e.to.is_none() {
                for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
                    let from = u32::from(rung.node_col.get(f as usize).copied().unwrap_or(0));
                    let yk = y_of(u32::from(row));
                    if from < col {
                        wire(&mut body, x_of(from), yk, x, yk, on(f));
                    }
                }
            }
            let mid = x + CELL_W / 2;
            match e.symbol {
                Symbol::Box => {
                    let h = u32::from(e.height) * CELL_H - 16;
                    for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
                        let yk = y_of(u32::from(row));
                        wire(&mut body, x, yk, x + 8, yk, on(f));
                    }
                    let _ = writeln!(
                        body,
                        r##"<rect x="{}" y="{}" width="{}" height="{h}" rx="3" fill="#ffffff" {}/>"##,
                        x + 8,
                        yc - CELL_H / 2 + 8,
                        CELL_W - 16,
                        stroke(powered)
                    );
                    let mut lines = vec![e.text.clone()];
                    lines.extend(e.values.iter().map(|v| values(v)));
                    for (j, l) in lines.iter().enumerate() {
                        let _ = writeln!(
                            body,
                            r#"<text class="box" x="{mid}" y="{}" text-anchor="middle">{}</text>"#,
                            yc - CELL_H / 2 + 24 + j as u32 * 14,
                            escape(&fit(l, 16))
                        );
                    }
                    if !e.comment.is_empty() {
                        let _ = writeln!(
                            body,
                            r##"<text class="note" x="{mid}" y="{}" text-anchor="middle" fill="#2a7a2a" font-size="9"><title>{}</title>{}</text>"##,
                            // Inside the box, along its bottom edge.
                            yc - CELL_H / 2 + 8 + h - 5,
                            escape(&e.comment),
                            escape(&fit(&e.comment, 22))
                        );
                    }
                }
                _ => {
                    let (l, r) = (mid - 12, mid + 12);
                    wire(&mut body, x, yc, l, yc, input_lit);
                    let out_lit = match e.to {
                        Some(to) => on(to),
                        None => false,
                    };
                    wire(&mut body, r, yc, x + CELL_W, yc, out_lit);
                    match e.symbol {
                        Symbol::Coil(kind) => {
                            let _ = writeln!(
                                body,
                                r#"<path class="coil" d="M{} {} a 14 14 0 0 0 0 28 M{} {} a 14 14 0 0 1 0 28" fill="none" {}/><text class="sym" x="{mid}" y="{}" text-anchor="middle" font-weight="bold">{}</text>"#,
                                l + 6,
                                yc - 14,
                                r - 6,
                                yc - 14,
                                stroke(powered),
                                yc + 4,
                                coil_letters(kind)
                            );
                        }
                        _ => {
                            let mark = match e.symbol {
                                Symbol::Contact { closed: true, .. } => "/",
                                Symbol::Contact {
                                    edge: Some(EdgeKind::Rising),
                                    ..
                                }
                                | Symbol::PowerEdge(EdgeKind::Rising) => "↑",
                                Symbol::Contact {
                                    edge: Some(EdgeKind::Falling),
                                    ..
                                }
                                | Symbol::PowerEdge(EdgeKind::Falling) => "↓",
                                Symbol::Invert => "NOT",
                                Symbol::Compare => "CMP",
                                _ => "",
                            };
                            let _ = writeln!(
                                body,
                                r#"<line class="contact" x1="{l}" y1="{}" x2="{l}" y2="{}" {}/><line class="contact" x1="{r}" y1="{}" x2="{r}" y2="{}" {}/><text class="sym" x="{mid}" y="{}" text-anchor="middle" font-weight="bold">{}</text>"#,
                                yc - 14,
                                yc + 14,
                                stroke(powered),
                                yc - 14,
                                yc + 14,
                                stroke(powered),
                                yc + 4,
                                mark
                            );
                        }
                    }
                    let _ = writeln!(
                        body,
                        r#"<text class="name" x="{mid}" y="{}" text-anchor="middle">{}</text>"#,
                        yc - 18,
                        escape(&fit(&e.text, 18))
                    );
                    if !e.comment.is_empty() {
                        let _ = writeln!(
                            body,
                            r##"<text class="note" x="{mid}" y="{}" text-anchor="middle" fill="#2a7a2a" font-size="9"><title>{}</title>{}</text>"##,
                            yc - 31,
                            escape(&e.comment),
                            escape(&fit(&e.comment, 22))
                        );
                    }
                }
            }
            body.push_str("</g>\n");
        }
        body.push_str("</g>\n");
        y = top + height + RUNG_GAP;
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{y}" viewBox="0 0 {width} {y}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="24" font-size="14">{}</text>"#,
        left,
        escape(title)
    );
    out.push_str(&body);
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(i: usize, name: &str) -> Element {
        Element::new(
            Symbol::Contact {
                closed: false,
                edge: None,
            },
            i,
            i + 1,
            name,
        )
    }

    fn coil(i: usize, name: &str) -> Element {
        Element::new(Symbol::Coil(CoilKind::Out), i, i + 1, name)
    }

    fn named<'a>(r: &'a Rung, name: &str) -> &'a Element {
        r.elements.iter().find(|e| e.operand == name).expect(name)
    }

    fn before(r: &Rung, name: &str) -> Vec<String> {
        let mut v: Vec<String> = r
            .before(named(r, name))
            .into_iter()
            .map(|e| e.map_or("rail".to_string(), |e| e.operand.clone()))
            .collect();
        v.sort();
        v
    }

    #[test]
    fn series_parallel_and_blocks_wire_as_the_stack_combines() {
        // (A·B + C) · (D + E) → Y
        let ladder = Ladder::build([
            Step::Load(c(0, "A")),
            Step::And(c(1, "B")),
            Step::Or(c(2, "C")),
            Step::Load(c(3, "D")),
            Step::Or(c(4, "E")),
            Step::AndBlock,
            Step::Output(coil(5, "Y")),
        ]);
        assert_eq!(ladder.rungs.len(), 1);
        let r = &ladder.rungs[0];
        assert_eq!(before(r, "A"), ["rail"]);
        assert_eq!(before(r, "B"), ["A"]);
        assert_eq!(before(r, "C"), ["rail"]);
        assert_eq!(before(r, "D"), ["B", "C"]);
        assert_eq!(before(r, "E"), ["B", "C"]);
        assert_eq!(before(r, "Y"), ["D", "E"]);
        // Power: A off, C on, E on → Y powered; D's wire lit through C.
        let p = RungPower::of(r, RungState::Done, |i| [false, true, true, false, true][i]);
        let y = r.elements.iter().position(|e| e.operand == "Y").unwrap();
        assert!(p.element[y]);
        let p = RungPower::of(r, RungState::Done, |i| [false, true, false, true, true][i]);
        assert!(!p.element[y], "A·B + C is off");
    }

    #[test]
    fn outputs_after_more_conditions_branch_at_the_fork() {
        // STR X1; OUT Y1; AND X2; OUT Y2 — then a new rung at STR.
        let ladder = Ladder::build([
            Step::Load(c(0, "X1")),
            Step::Output(coil(1, "Y1")),
            Step::And(c(2, "X2")),
            Step::Output(coil(3, "Y2")),
            Step::Load(c(4, "X3")),
            Step::Output(coil(5, "Y3")),
        ]);
        assert_eq!(ladder.rungs.len(), 2);
        let r = &ladder.rungs[0];
        assert_eq!(before(r, "Y1"), ["X1"]);
        assert_eq!(before(r, "X2"), ["X1"]);
        assert_eq!(before(r, "Y2"), ["X2"]);
        assert_eq!(named(r, "Y1").col, named(r, "Y2").col, "coils line up");
        assert_ne!(named(r, "Y1").row, named(r, "Y2").row);
    }

    #[test]
    fn branch_stack_and_boxes_with_legs() {
        // LOD A; BPS; AND B; OUT Q1; BPP; AND C; OUT Q2
        let ladder = Ladder::build([
            Step::Load(c(0, "A")),
            Step::Push,
            Step::And(c(1, "B")),
            Step::Output(coil(2, "Q1")),
            Step::Pop,
            Step::And(c(3, "C")),
            Step::Output(coil(4, "Q2")),
            // Reset leg, pulse leg, CNT.
            Step::Load(c(5, "R")),
            Step::Load(c(6, "P")),
            Step::Boxed(Element::new(Symbol::Box, 7, 8, "CNT"), 2),
        ]);
        let r = &ladder.rungs[0];
        assert_eq!(before(r, "B"), ["A"]);
        assert_eq!(before(r, "C"), ["A"]);
        assert_eq!(before(r, "Q2"), ["C"]);
        let cnt = &ladder.rungs[1];
        let b = named(cnt, "CNT");
        assert_eq!(b.from.len(), 2);
        assert_eq!(b.height, 2);
        assert_eq!(before(cnt, "CNT"), ["P", "R"]);
        assert_eq!(
            named(cnt, "R").row,
            b.row,
            "the first leg enters at the top"
        );
        assert_eq!(named(cnt, "P").row, b.row + 1);
    }

    #[test]
    fn only_an_evaluated_rung_has_power() {
        let ladder = Ladder::build([Step::Load(c(0, "X1")), Step::Output(coil(1, "Y1"))]);
        let r = &ladder.rungs[0];
        for state in [RungState::NotYet, RungState::NotRun, RungState::MasterOff] {
            let p = RungPower::of(r, state, |_| true);
            assert_eq!(
                p.element,
                [true, false],
                "{state:?}: the contact shows its bit"
            );
            assert!(!p.node[1], "{state:?}: no power past it");
        }
        let p = RungPower::of(r, RungState::Done, |_| true);
        assert_eq!(p.element, [true, true]);
    }

    #[test]
    fn svg_carries_the_attributes() {
        let ladder = Ladder::build([Step::Load(c(0, "X<1")), Step::Output(coil(1, "Y1"))]);
        let power = vec![RungPower::of(&ladder.rungs[0], RungState::Done, |_| true)];
        let s = svg(&ladder, &power, "t", &|v| v.to_string(), &|_| None);
        assert!(s.contains(r#"data-rung="0""#));
        assert!(s.contains(r#"data-line="1" data-operand="X&lt;1" data-powered="1""#));
        assert!(s.contains(r#"data-line="2" data-operand="Y1" data-powered="1""#));
    }
}
