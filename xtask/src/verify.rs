use std::fmt::Write as _;
use tumble::verify::{self, ErrorRow, fitted_order};

/// All convergence rows of the verification cases.
pub fn all_rows() -> Vec<ErrorRow> {
    verify::convergence_rows()
}

pub fn run(_args: &[String]) -> i32 {
    let rows = all_rows();
    let mut csv = format!("{}\n", ErrorRow::CSV_HEADER);
    println!("{:<22} {:<20} {:<25} {:>8} {:>12} {:>12} {:>7}", "case", "measure", "integrator", "dt/T", "dt [s]", "error", "order");
    for group in groups(&rows) {
        let order = fitted_order(&group[group.len() - 4..]);
        for (k, r) in group.iter().enumerate() {
            let o = if k + 1 == group.len() { format!("{order:7.2}") } else { String::new() };
            println!(
                "{:<22} {:<20} {:<25} {:>8} {:>12.4e} {:>12.4e} {:>7}",
                r.case,
                r.measure,
                r.integrator.name(),
                format!("1/{}", r.steps_per_scale),
                r.dt,
                r.error,
                o
            );
            let _ = writeln!(csv, "{}", r.csv());
        }
    }
    let _ = std::fs::create_dir_all("docs");
    if let Err(e) = std::fs::write("docs/verification.csv", csv) {
        eprintln!("cannot write docs/verification.csv: {e}");
        return 1;
    }
    0
}

/// Rows grouped by (case, measure, integrator), in order of first appearance.
pub fn groups(rows: &[ErrorRow]) -> Vec<Vec<&ErrorRow>> {
    let mut out: Vec<Vec<&ErrorRow>> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|g| g[0].case == r.case && g[0].measure == r.measure && g[0].integrator == r.integrator) {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    out
}
