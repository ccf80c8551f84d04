//! A benchmark's result as a table: a title, column names and rows of cells, printed as the
//! Markdown the benchmarks page quotes.

use std::fmt::Write as _;

/// Rows under named columns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    /// A line printed above the table (blank lines around it), if any.
    pub title: Option<String>,
    /// The column names.
    pub columns: Vec<String>,
    /// The rows, one cell per column.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these columns and no rows.
    pub fn new(title: Option<String>, columns: &[&str]) -> Table {
        Table {
            title,
            columns: columns.iter().map(|c| (*c).to_owned()).collect(),
            rows: Vec::new(),
        }
    }

    /// Adds a row.
    pub fn push(&mut self, row: Vec<String>) {
        self.rows.push(row);
    }

    /// The table as Markdown (a pipe table, the title above it).
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        if let Some(t) = &self.title {
            let _ = write!(s, "\n{t}\n\n");
        }
        let line = |cells: &[String]| format!("| {} |\n", cells.join(" | "));
        s.push_str(&line(&self.columns));
        s.push_str(&format!("|{}\n", "---|".repeat(self.columns.len())));
        for r in &self.rows {
            s.push_str(&line(r));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_has_a_header_a_rule_and_one_line_per_row() {
        let mut t = Table::new(Some("Cube size".into()), &["setting", "ms"]);
        t.push(vec!["64²".into(), "1.5".into()]);
        t.push(vec!["128²".into(), "2.0".into()]);
        assert_eq!(
            t.markdown(),
            "\nCube size\n\n| setting | ms |\n|---|---|\n| 64² | 1.5 |\n| 128² | 2.0 |\n"
        );
        assert_eq!(Table::new(None, &["a"]).markdown(), "| a |\n|---|\n");
    }
}
