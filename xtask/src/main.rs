//! `cargo xtask verify` prints the verification table and writes it as CSV;
//! `cargo xtask conformance` runs the conformance suite on every backend present.

mod charts;
mod conformance;
mod svg;
mod sweep;
mod verify;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let code = match args.first().map(String::as_str) {
        Some("verify") => verify::run(&args[1..]),
        Some("conformance") => conformance::run(&args[1..]),
        Some("charts") => charts::run(&args[1..]),
        Some("sweep") => sweep::run(&args[1..]),
        _ => {
            eprintln!(
                "usage: cargo xtask <verify|conformance|charts|sweep>\n  verify       the analytic verification table (case x integrator x dt x error x order), CSV in docs/verification.csv\n  conformance  the cross-backend conformance table; exits 1 on any failure\n  charts       speed-vs-accuracy, stability-map and convergence charts (SVG + CSV) in docs/charts/\n  sweep        agglomeration in a Taylor-Green vortex over Stk x Sy (cargo xtask sweep --help): CSV and heat maps in docs/agglomeration/"
            );
            2
        }
    };
    std::process::exit(code);
}
