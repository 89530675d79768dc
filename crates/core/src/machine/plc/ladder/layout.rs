//! The layout of a wired rung in grid cells: each node's column, each element's row, and
//! the horizontal fillers and vertical wires between them.

use super::{Filler, MAX_RUNG_COLUMNS, MAX_RUNG_ROWS, NodeId, RAIL, Rung, Vertical};

/// The rows an oversized rung's note takes.
const OVERSIZED_ROWS: u16 = 2;

/// Cells the row search may look at in one rung: far past any rung that fits the bounds as
/// people draw them, so only a pathological shape gives up.
const CELL_VISITS: u64 = 20_000_000;

/// Columns, rows, fillers and verticals of a wired rung. A rung wider than
/// [`MAX_RUNG_COLUMNS`] or taller than [`MAX_RUNG_ROWS`] is not laid out: it gets its
/// `oversized` note, which the panel and the SVG draw instead, and the work stays linear in
/// its elements (a rung of 200,000 series contacts used to take gigabytes).
pub(super) fn layout(rung: &mut Rung) {
    let n = rung.nodes as usize;
    // Longest path from the rail. Every element ends at a newer node, so taking elements in
    // the order of their output node settles each node's column before it is read.
    let mut col = vec![0u32; n];
    let mut order: Vec<usize> = (0..rung.elements.len()).collect();
    order.sort_by_key(|&i| rung.elements[i].to);
    for &i in &order {
        let e = &rung.elements[i];
        if let (Some(to), Some(&from)) = (e.to, e.from.first())
            && let (Some(&f), Some(&t)) = (col.get(from as usize), col.get(to as usize))
        {
            col[to as usize] = t.max(f.saturating_add(1));
        }
    }
    let last_col = rung
        .elements
        .iter()
        .filter(|e| e.to.is_none())
        .flat_map(|e| {
            e.from
                .iter()
                .map(|&f| col.get(f as usize).copied().unwrap_or(0))
        })
        .chain(col.iter().copied())
        .max()
        .unwrap_or(0);
    // Coils and boxes each take rows of their own in the last column.
    let end_rows: usize = (rung.elements.iter())
        .filter(|e| e.to.is_none())
        .map(|e| e.from.len().max(1))
        .sum();
    if last_col >= MAX_RUNG_COLUMNS as u32 || end_rows > MAX_RUNG_ROWS {
        return oversized(rung, last_col as usize + 1, end_rows);
    }
    let col: Vec<u16> = col.into_iter().map(|c| c as u16).collect();
    let last_col = last_col as u16;
    // Rows: cells taken, per row.
    let mut taken: Vec<Vec<bool>> = Vec::new();
    let width = usize::from(last_col) + 1;
    let mut node_row: Vec<Option<u16>> = vec![None; n];
    node_row[RAIL as usize] = Some(0);
    let visits = std::cell::Cell::new(0u64);
    let fits = |taken: &Vec<Vec<bool>>, row: usize, a: usize, b: usize| {
        visits.set(visits.get() + (b - a) as u64);
        taken.get(row).is_none_or(|r| r[a..b].iter().all(|t| !t))
    };
    let mut fillers = Vec::new();
    for k in 0..rung.elements.len() {
        let e = &mut rung.elements[k];
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
            if row + height > MAX_RUNG_ROWS || visits.get() > CELL_VISITS {
                let rows = row + height;
                return oversized(rung, width, rows);
            }
        }
        if row + height > MAX_RUNG_ROWS {
            return oversized(rung, width, row + height);
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
    rung.oversized = None;
}

/// A rung too large to draw: one row, no wires, and the note saying why.
fn oversized(rung: &mut Rung, columns: usize, rows: usize) {
    let (first, last) = (
        rung.first_line(),
        rung.elements.iter().map(|e| e.line).max().unwrap_or(0),
    );
    rung.oversized = Some(format!(
        "Rung of lines {first}–{last} not drawn: its {} elements need {columns} × {} cells, and the ladder draws rungs of at most {MAX_RUNG_COLUMNS} columns and {MAX_RUNG_ROWS} rows. The program runs as written.",
        rung.elements.len(),
        rows.max(1),
    ));
    for e in &mut rung.elements {
        e.col = 0;
        e.row = 0;
        e.height = 1;
        e.from_col = 0;
        e.leg_rows = vec![0; e.from.len().max(1)];
    }
    // Room for the note, wrapped, in the panel.
    rung.rows = OVERSIZED_ROWS;
    rung.node_col = vec![0; rung.nodes as usize];
    rung.last_col = 0;
    rung.fillers = Vec::new();
    rung.verticals = Vec::new();
}
