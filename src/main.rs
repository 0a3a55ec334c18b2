//! The `stfit` command line.

fn main() {
    println!("stfit {}", env!("CARGO_PKG_VERSION"));
}
