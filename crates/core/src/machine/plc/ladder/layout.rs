//! The layout of a wired rung in grid cells: each node's column, each element's row, and
//! the horizontal fillers and vertical wires between them.

use super::{Filler, NodeId, RAIL, Rung, Vertical};

/// Columns, rows, fillers and verticals of a wired rung.
pub(super) fn layout(rung: &mut Rung) {
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
