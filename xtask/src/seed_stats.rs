//! Two variants of one study run over the same seeds: each one's mean, standard deviation and
//! standard error, and their difference in combined standard errors, as a CSV's closing lines.

use std::fmt::Write as _;

/// Mean, sample standard deviation and standard error of the mean.
pub(crate) fn mean_sd_se(x: &[f64]) -> (f64, f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let sd = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    (mean, sd, sd / n.sqrt())
}

/// Appends `# a: mean …`, `# b: mean …` and `# difference a - b: …` to `csv`, in `unit` with
/// `digits` decimals.
pub(crate) fn compare(csv: &mut String, (a_name, a): (&str, &[f64]), (b_name, b): (&str, &[f64]), unit: &str, digits: usize) {
    let ((am, asd, ase), (bm, bsd, bse)) = (mean_sd_se(a), mean_sd_se(b));
    for (name, m, sd, se) in [(a_name, am, asd, ase), (b_name, bm, bsd, bse)] {
        let _ = writeln!(csv, "# {name}: mean {m:.digits$} {unit}, sd {sd:.digits$}, standard error {se:.digits$}");
    }
    let _ = writeln!(
        csv,
        "# difference {a_name} - {b_name}: {:.digits$} {unit} ({:+.2} %), {:.2} combined standard errors",
        am - bm,
        100.0 * (am / bm - 1.0),
        (am - bm) / (ase.powi(2) + bse.powi(2)).sqrt()
    );
}

/// Prints `csv` and writes it to docs/charts/`name`.csv; the exit code.
pub(crate) fn write_csv(name: &str, csv: &str) -> i32 {
    print!("{csv}");
    let path = crate::mill::root().join("docs/charts").join(format!("{name}.csv"));
    match std::fs::write(&path, csv) {
        Ok(()) => {
            eprintln!("wrote {}", path.display());
            0
        }
        Err(e) => {
            eprintln!("cannot write {}: {e}", path.display());
            1
        }
    }
}
