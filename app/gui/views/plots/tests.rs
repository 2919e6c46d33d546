//! The plots' value grid, probe values and decimation.

use egui_plot::GridInput;

use super::execution::value_at;
use super::plot::{decimate, value_grid};
use crate::gui::theme::{PLOT_HEIGHT, VALUE_GRID_GAP};

#[test]
fn value_grids_step_by_one_two_or_five_and_keep_labels_apart() {
    for (lo, hi) in [
        (0.0, 950.0),
        (0.0, 2700.0),
        (-3.0, 0.4),
        (0.0, 3.3e6),
        (500.0, 501.0),
    ] {
        let marks = value_grid(GridInput {
            bounds: (lo, hi),
            base_step_size: 0.0,
        });
        assert!(marks.len() >= 2, "{lo}..{hi}: {} marks", marks.len());
        let step = marks[1].value - marks[0].value;
        let ten = 10f64.powf(step.log10().floor());
        let k = (step / ten).round();
        assert!([1.0, 2.0, 5.0].contains(&k), "{lo}..{hi}: step {step}");
        let px = step / (hi - lo) * f64::from(PLOT_HEIGHT);
        assert!(
            px >= f64::from(VALUE_GRID_GAP) - 1e-9,
            "{lo}..{hi}: {px} px"
        );
        assert!(marks.iter().all(|m| lo <= m.value && m.value <= hi));
    }
    // The peak plot of the bundled plan: 0 to about 950 W gets 0, 200, ... 800.
    let marks = value_grid(GridInput {
        bounds: (0.0, 950.0),
        base_step_size: 0.0,
    });
    let values: Vec<f64> = marks.iter().map(|m| m.value).collect();
    assert_eq!(values, [0.0, 200.0, 400.0, 600.0, 800.0]);
    assert!(
        value_grid(GridInput {
            bounds: (1.0, 1.0),
            base_step_size: 0.0
        })
        .is_empty()
    );
}

#[test]
fn values_between_points_are_linear_and_a_jump_takes_the_later_value() {
    let series = [[0.0, 10.0], [10.0, 20.0], [10.0, 5.0], [20.0, 5.0]];
    assert_eq!(value_at(&series, -1.0), None);
    assert_eq!(value_at(&series, 0.0), Some(10.0));
    assert_eq!(value_at(&series, 5.0), Some(15.0));
    assert_eq!(value_at(&series, 10.0), Some(5.0));
    assert_eq!(value_at(&series, 20.0), Some(5.0));
    assert_eq!(value_at(&series, 21.0), None);
    assert_eq!(value_at(&[], 0.0), None);
}

#[test]
fn decimation_keeps_each_columns_envelope_and_time_order() {
    // A dense step function: 10,000 alternating steps over [0, 100,000).
    let mut series = Vec::new();
    for k in 0..10_000 {
        let (x, y) = (
            f64::from(k) * 10.0,
            f64::from(k % 7) * 3.0 + f64::from(k / 1000),
        );
        series.push([x, y]);
        series.push([x + 10.0, y]);
    }
    let (start, end, width) = (20_000.0, 80_000.0, 300.0);
    let out = decimate(&series, start, end, width);
    assert!(out.len() <= 4 * (width as usize + 3), "{}", out.len());
    // Between columns the line is flat (the series holds its value): no
    // slanted strokes at any zoom.
    for w in out.windows(2) {
        if w[0][0] != w[1][0] {
            assert_eq!(w[0][1], w[1][1], "slanted: {w:?}");
        }
    }
    assert!(out.windows(2).all(|w| w[0][0] <= w[1][0]), "time order");
    let spp = (end - start) / width;
    for c in 0..width as usize {
        let (a, b) = (start + c as f64 * spp, start + (c + 1) as f64 * spp);
        let inside = |p: &&[f64; 2]| p[0] >= a && p[0] < b;
        let ys = |v: &[[f64; 2]]| {
            let v: Vec<f64> = v.iter().filter(inside).map(|p| p[1]).collect();
            (
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            )
        };
        assert_eq!(ys(&series), ys(&out), "column {c}");
    }
    // Sparse data is left exact.
    let sparse = vec![
        [0.0, 1.0],
        [50_000.0, 1.0],
        [50_000.0, 4.0],
        [90_000.0, 4.0],
    ];
    assert_eq!(decimate(&sparse, 0.0, 100_000.0, 800.0), sparse);
}
