//! `cargo xtask verify` prints the verification table and writes it as CSV;
//! `cargo xtask conformance` runs the conformance suite on every backend present.

mod charts;
mod conformance;
mod friction_charts;
mod mill;
mod svg;
mod verify;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let code = match args.first().map(String::as_str) {
        Some("verify") => verify::run(&args[1..]),
        Some("conformance") => conformance::run(&args[1..]),
        Some("charts") => charts::run(&args[1..]),
        Some("mill") => mill::mill(&args[1..]),
        Some("hopper") => mill::hopper(&args[1..]),
        _ => {
            eprintln!(
                "usage: cargo xtask <verify|conformance|charts|mill|hopper>\n  verify       the analytic verification table (case x integrator x dt x error x order), CSV in docs/verification.csv\n  conformance  the cross-backend conformance table; exits 1 on any failure\n  charts       speed-vs-accuracy, stability-map and convergence charts (SVG + CSV) in docs/charts/\n  mill         ball-mill power draw and charge profile against speed and filling (docs/charts/mill_power.*)\n  hopper       hopper discharge rate against orifice width (docs/charts/hopper_discharge.*)"
            );
            2
        }
    };
    std::process::exit(code);
}
