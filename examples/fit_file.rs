//! Fit a measurement file from code: load it, fit the four models of `stfit DATA --model all`,
//! print the table and store the fits, each of which carries the model it fitted.
//!
//! Run with `cargo run --release --example fit_file [DATA.csv]` (default: the shipped example
//! data, `fits/example.csv`).

use stfit_fit::{FitOptions, FitsFile, all_models, fit_dataset, load_path};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap_or("fits/example.csv".into());
    let data = load_path(path.as_ref())?;
    let fits = fit_dataset(&data, &all_models(), &FitOptions::default(), &|_, _| {})?;
    print!("{}", stfit_report::fits_table(&fits));

    // A fit knows its model: evaluate the best Student-T of the first sample straight through.
    let best = fits
        .iter()
        .filter(|f| f.sample == data.samples[0].name)
        .min_by(|a, b| a.rmse_sqrt_l.total_cmp(&b.rmse_sqrt_l))
        .expect("at least one fit");
    let l = best.model.predict(&[(0.0, 180.0)])?;
    println!(
        "\n{}: L at normal incidence, straight through = {:.5}",
        best.label(),
        l[0]
    );

    let out = std::env::temp_dir().join("stfit-example-fits.json");
    std::fs::write(&out, FitsFile::new(fits).to_json())?;
    println!("fits stored in {}", out.display());
    Ok(())
}
