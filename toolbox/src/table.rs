//! Plain-text tables whose columns line up whatever their contents: each column as wide
//! as its widest cell (long map names, large numbers), text left-aligned and figures
//! right-aligned. A row may end in free text after its columns (a verdict), and a short
//! row (a map, then its error) writes its last cell unpadded.

/// How a column's cells are aligned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    Left,
    Right,
}

/// Whether cell `c` of a row of `len` cells is padded to its column's width: every
/// cell of a column but a short row's last one.
fn padded(c: usize, len: usize, columns: usize) -> bool {
    c < columns && (len > columns || c + 1 < len || len == columns)
}

/// Lays out `rows` in the columns `aligns`, `gap` spaces apart (see the module). Cells
/// past the columns are free text, written as they are; trailing blanks are trimmed.
pub fn lines(rows: &[Vec<String>], aligns: &[Align], gap: usize) -> Vec<String> {
    let widths: Vec<usize> = (0..aligns.len())
        .map(|c| {
            rows.iter()
                .filter(|r| padded(c, r.len(), aligns.len()))
                .map(|r| r[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let sep = " ".repeat(gap);
    rows.iter()
        .map(|r| {
            let mut line = String::new();
            for (c, cell) in r.iter().enumerate() {
                if c > 0 {
                    line.push_str(&sep);
                }
                if !padded(c, r.len(), aligns.len()) {
                    line.push_str(cell);
                    continue;
                }
                let pad = " ".repeat(widths[c].saturating_sub(cell.chars().count()));
                match aligns[c] {
                    Align::Left => {
                        line.push_str(cell);
                        line.push_str(&pad);
                    }
                    Align::Right => {
                        line.push_str(&pad);
                        line.push_str(cell);
                    }
                }
            }
            line.trim_end().to_string()
        })
        .collect()
}

/// The character positions where each cell of `line` ends, given the cells in order
/// (for tests of alignment: a column is aligned when its cells end, right-aligned, or
/// start, left-aligned, at one position in every row).
pub fn cell_spans(line: &str, cells: &[&str]) -> Vec<(usize, usize)> {
    let mut at = 0;
    let mut out = Vec::new();
    for cell in cells {
        let Some(k) = line[at..].find(cell) else {
            break;
        };
        let start = line[..at + k].chars().count();
        out.push((start, start + cell.chars().count()));
        at += k + cell.len();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(cells: &[&str]) -> Vec<String> {
        cells.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn columns_line_up_with_long_and_large_cells() {
        let rows = vec![
            row(&["map", "bytes", "verdict"]),
            row(&["a_very_long_map_name_of_a_real_game_level", "1", "ok"]),
            row(&["b", "123456789012345678", "REGRESSION"]),
            row(&["c", "failed: the map is gone"]),
        ];
        let out = lines(&rows, &[Align::Left, Align::Right, Align::Left], 2);
        let spans: Vec<_> = rows[..3]
            .iter()
            .zip(&out)
            .map(|(r, l)| cell_spans(l, &r.iter().map(|s| s.as_str()).collect::<Vec<_>>()))
            .collect();
        // The figure column ends, and the verdict starts, at one position in every row.
        assert!(spans.iter().all(|s| s[1].1 == spans[0][1].1), "{out:#?}");
        assert!(spans.iter().all(|s| s[2].0 == spans[0][2].0), "{out:#?}");
        // A short row: the map padded like the others, then its error.
        assert_eq!(out[3], format!("{:<41}  failed: the map is gone", "c"));
    }
}
