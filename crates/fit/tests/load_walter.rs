//! The published Walter et al. 2007 measurements load unchanged (read from the shared folder,
//! `../shared` next to the repository, or `$STFIT_SHARED`; never copied into the project).

use stfit_fit::load::load_path;

#[test]
fn walter_measurements_load_with_three_samples_of_300_points() {
    let Some(path) = stfit_test_support::walter_measurements(
        "walter_measurements_load_with_three_samples_of_300_points",
    ) else {
        return;
    };
    let data = load_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<_> = data.samples.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["frosted", "etched", "ground"]);
    for sample in &data.samples {
        assert_eq!(sample.points.len(), 300, "{}", sample.name);
        let mut incidences: Vec<f64> = sample
            .points
            .iter()
            .map(|p| p.in_plane_angles().unwrap().0)
            .collect();
        incidences.sort_by(f64::total_cmp);
        incidences.dedup();
        assert_eq!(incidences, [0.0, 30.0, 60.0, 80.0], "{}", sample.name);
        assert!(
            sample
                .points
                .iter()
                .all(|p| p.weight == 1.0 && p.value >= 0.0)
        );
    }
    // The file gives sqrt(L): the loader squares the value of the first data row, read here
    // independently of the loader (the data are never copied into the project).
    let text = std::fs::read_to_string(&path).unwrap();
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    let field = |i: usize| row[i].trim().parse::<f64>().unwrap();
    let first = data.samples[0].points[0];
    assert_eq!(first.in_plane_angles(), Some((field(1), field(2))));
    assert!((first.value - field(3).powi(2)).abs() < 1e-15);
}
