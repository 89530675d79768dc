//! Breakpoints follow their lines when the program text is edited.

use std::collections::BTreeSet;

/// Move 1-based line numbers from `old` text to `new` text: lines in the unchanged head stay,
/// lines in the unchanged tail move with it, lines inside the changed middle stay where they
/// were (clamped to the new length).
pub fn remap_lines(old: &str, new: &str, lines: &BTreeSet<usize>) -> BTreeSet<usize> {
    let map = line_mover(old, new);
    lines.iter().filter_map(|&l| map(l)).collect()
}

/// Where each 1-based line of `old` is in `new` (by the rule of [`remap_lines`]); `None` when
/// it is past the end of the new text.
pub fn line_mover(old: &str, new: &str) -> impl Fn(usize) -> Option<usize> + use<> {
    let old_lines: Vec<&str> = old.lines().collect();
    let new_lines: Vec<&str> = new.lines().collect();
    let unchanged = old.is_empty();
    let head = old_lines
        .iter()
        .zip(&new_lines)
        .take_while(|(a, b)| a == b)
        .count();
    let max_tail = old_lines.len().min(new_lines.len()) - head;
    let tail = old_lines
        .iter()
        .rev()
        .zip(new_lines.iter().rev())
        .take(max_tail)
        .take_while(|(a, b)| a == b)
        .count();
    let old_tail_start = old_lines.len() - tail;
    let shift = new_lines.len() as i64 - old_lines.len() as i64;
    let new_len = new_lines.len();
    move |line: usize| {
        if unchanged {
            return Some(line);
        }
        let index = line.checked_sub(1)?;
        let moved = if index < head {
            index as i64
        } else if index >= old_tail_start {
            index as i64 + shift
        } else {
            index.min(new_len.saturating_sub(1)) as i64
        };
        (moved >= 0 && (moved as usize) < new_len.max(1)).then_some(moved as usize + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn breakpoints_follow_inserted_and_deleted_lines() {
        let bps: BTreeSet<usize> = [1, 3, 5].into();
        let old = "a\nb\nc\nd\ne";
        assert_eq!(
            remap_lines(old, "a\nnew\nb\nc\nd\ne", &bps),
            [1, 4, 6].into()
        );
        assert_eq!(remap_lines(old, "a\nc\nd\ne", &bps), [1, 2, 4].into());
        assert_eq!(remap_lines(old, "a\nb\nC\nd\ne", &bps), [1, 3, 5].into());
    }
}
