//! How [`Ladder::build`] wires the boolean stack's steps into rungs: blocks of elements
//! joined at nodes, in series and in parallel, outputs and boxes rooted at the rail.

use super::layout::layout;
use super::{Element, Ladder, NodeId, RAIL, Rung, Step};

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
        rungs.push(Rung {
            elements,
            nodes: next,
            ..Default::default()
        });
    }
}

impl Ladder {
    /// The diagram of a program given as boolean-stack steps in program order, laid out.
    pub fn build(steps: impl IntoIterator<Item = Step>) -> Ladder {
        let mut ladder = Ladder::wire(steps);
        ladder.lay_out();
        ladder
    }

    /// Lay every rung out in cells (the wiring is there already): done when something draws
    /// the diagram, not when a program is assembled.
    pub fn lay_out(&mut self) {
        for rung in &mut self.rungs {
            layout(rung);
        }
        // A rung too large to draw does not push every other rung's coils to the right.
        self.last_col = (self.rungs.iter())
            .filter(|r| r.oversized.is_none())
            .map(|r| r.last_col)
            .max()
            .unwrap_or(0);
    }

    /// The rungs and how their elements connect, not laid out yet: what the assemblers keep
    /// (duplicate coils and the I/O board need no more).
    pub fn wire(steps: impl IntoIterator<Item = Step>) -> Ladder {
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
        Ladder { rungs, last_col: 0 }
    }
}
