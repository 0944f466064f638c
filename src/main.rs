use clap::Parser;

fn main() {
    std::process::exit(tumble::cli::main_with(tumble::cli::Cli::parse()));
}
