//! The figure test on synthetic charts: it passes a clean chart and fails each defect it
//! guards against (a legend over data, a mark outside its axes, overlapping labels), so a
//! pass on the report's figures (`tests/thesis/report.rs`) means something.

mod figure_check;
#[path = "figure_check/numbering.rs"]
mod numbering;
#[path = "figure_check/scale.rs"]
mod scale;

use figure_check::problems;
use mass_spring_report::crate_root;
use mass_spring_report::plot::{
    layout, Align, Axis, Chart, Corner, LegendPlace, Line, Marker, Panel, Rgb, Series,
    COLUMN_WIDTH_MM, FULL_WIDTH_MM,
};

/// A panel with a rising diagonal of markers from its lower left to its upper right corner.
fn rising() -> Panel {
    let mut p = Panel::new(Axis::linear("t (s)"), Axis::log("E (J)"));
    let points: Vec<(f64, f64)> = (0..=20)
        .map(|i| (i as f64, 10f64.powf(i as f64 / 4.0)))
        .collect();
    p.series.push(
        Series::line("rising", points.clone(), Rgb(0, 0, 0)).with_marker(Marker::Circle, true),
    );
    p.series.push(Series::line(
        "rising too",
        points.iter().map(|q| (q.0, q.1 / 2.0)).collect(),
        Rgb(200, 0, 0),
    ));
    p
}

fn check(chart: &Chart) -> Vec<String> {
    let l = layout(chart).unwrap();
    problems("test", &l, &l.svg())
}

#[test]
fn a_clean_chart_passes() {
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![rising()]));
    assert!(found.is_empty(), "{found:#?}");
    let found = check(&Chart::new(FULL_WIDTH_MM, 60.0, vec![rising(), rising()]));
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn a_legend_moved_onto_data_fails() {
    let mut p = rising();
    p.legend = LegendPlace::Inside(Corner::UpperLeft);
    assert!(
        check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p.clone()])).is_empty(),
        "the upper left is free"
    );
    p.legend = LegendPlace::Inside(Corner::UpperRight);
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(
        found.iter().any(|f| f.contains("covers a data mark")),
        "{found:#?}"
    );
}

#[test]
fn a_label_on_a_line_or_on_another_label_fails() {
    let mut p = rising();
    p.label(
        (10.0, 10f64.powf(2.5)),
        (0.0, 0.0),
        Align::Middle,
        "on the line",
        Rgb(0, 0, 0),
    );
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(
        found.iter().any(|f| f.contains("\"on the line\" covers")),
        "{found:#?}"
    );
    let mut p = rising();
    p.label((2.0, 1e4), (0.0, 0.0), Align::Start, "first", Rgb(0, 0, 0));
    p.label((2.0, 1e4), (4.0, 2.0), Align::Start, "second", Rgb(0, 0, 0));
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(found.iter().any(|f| f.contains("overlap")), "{found:#?}");
}

#[test]
fn a_legend_over_a_label_fails() {
    let mut p = rising();
    p.legend = LegendPlace::Inside(Corner::UpperLeft);
    p.label((1.0, 1e4), (0.0, 0.0), Align::Start, "note", Rgb(0, 0, 0));
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(
        found.iter().any(|f| f.contains("covers text \"note\"")),
        "{found:#?}"
    );
}

#[test]
fn a_mark_outside_its_axes_fails() {
    let mut p = rising();
    // A fixed range that ends on the last point: half its marker pokes out of the frame.
    p.x = Axis::linear("t (s)").range(0.0, 20.0);
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(
        found.iter().any(|f| f.contains("outside its axes")),
        "{found:#?}"
    );
}

#[test]
fn a_chart_too_small_for_its_panels_is_an_error() {
    let err = layout(&Chart::new(20.0, 20.0, vec![rising()])).unwrap_err();
    assert!(err.to_string().contains("does not fit"), "{err}");
}

#[test]
fn two_series_told_apart_by_label_only_fail() {
    let mut p = rising();
    let twin = p.series[1].clone();
    p.series.push(Series {
        label: "same look".into(),
        points: twin.points.iter().map(|q| (q.0, q.1 / 4.0)).collect(),
        ..twin.clone()
    });
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p.clone()]));
    assert!(
        found
            .iter()
            .any(|f| f.contains("\"rising too\" and \"same look\" of panel 1 share marker")),
        "{found:#?}"
    );
    // A colour of its own is not enough: without colour they look the same.
    let mut recoloured = p.clone();
    recoloured.series.last_mut().unwrap().style.color = Rgb(0, 0, 200);
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![recoloured]));
    assert!(
        found.iter().any(|f| f.contains("share marker and dash")),
        "{found:#?}"
    );
    // A dash of its own tells it apart.
    let last = p.series.last_mut().unwrap();
    last.style.line = Line::Dashed;
    assert!(check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p])).is_empty());
}

#[test]
fn a_legend_entry_without_a_mark_fails() {
    let mut p = rising();
    p.series[1] = p.series[1].clone().with_line(Line::None);
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(
        found
            .iter()
            .any(|f| f.contains("legend entry \"rising too\" has no visible mark")),
        "{found:#?}"
    );
}

#[test]
fn a_series_hidden_under_another_fails() {
    let mut p = rising();
    // Drawn first, then covered point for point by a wider solid line with the same markers.
    let under = Series::line("under", p.series[0].points.clone(), Rgb(0, 0, 200))
        .with_marker(Marker::Circle, true);
    p.series.insert(0, under);
    p.series[1] = p.series[1].clone().with_weight(2.0);
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p.clone()]));
    assert!(
        found
            .iter()
            .any(|f| f.contains("\"under\" is hidden under \"rising\"")),
        "{found:#?}"
    );
    // Drawn last it shows.
    let under = p.series.remove(0);
    p.series.push(under);
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(!found.iter().any(|f| f.contains("hidden")), "{found:#?}");
}

#[test]
fn figures_out_of_order_unnumbered_lettered_or_uncited_fail() {
    use numbering::{numbering_problems, uncited};
    let good = "See [Figure 1](#f1) and [Figure 16](#f16).\n\n\
                <a id=\"f1\"></a>![Figure 1](figures/fig01-cloth.svg)\n\n*Figure 1. Cloth.*\n\n\
                <a id=\"f16\"></a>![Figure 16](figures/parity.svg)\n\n*Figure 16. Parity.*\n\n\
                - [`data/parity.csv`](data/parity.csv): the points of [Figure 16](#f16).\n";
    assert!(
        numbering_problems(good, 16).is_empty(),
        "{:?}",
        numbering_problems(good, 16)
    );
    assert!(uncited(good).is_empty());
    // Ours before the thesis's: out of order.
    let swapped = "<a id=\"f16\"></a>![Figure 16](figures/parity.svg)\n\n*Figure 16. Parity.*\n\n\
                   <a id=\"f1\"></a>![Figure 1](figures/fig01-cloth.svg)\n\n*Figure 1. Cloth.*\n";
    let found = numbering_problems(swapped, 16);
    assert!(
        found.iter().any(|f| f.contains("Figure 1 after Figure 16")),
        "{found:?}"
    );
    // A figure without a numbered caption, one with a letter, one numbered off the sequence.
    let unnumbered = good.replace("*Figure 16. Parity.*", "*Parity.*");
    let found = numbering_problems(&unnumbered, 16);
    assert!(
        found.iter().any(|f| f.contains("has no numbered caption")),
        "{found:?}"
    );
    let lettered = good.replace("Figure 16](#f16)", "Figure B1](#fB1)");
    let found = numbering_problems(&lettered, 16);
    assert!(found.iter().any(|f| f.contains("Figure B1")), "{found:?}");
    let skipped = good.replace("Figure 16", "Figure 17");
    let found = numbering_problems(&skipped, 16);
    assert!(
        found.iter().any(|f| f.contains("is Figure 17, not 16")),
        "{found:?}"
    );
    // Cited only in its own caption and in the data list: uncited.
    let caption_only = good.replace(
        "See [Figure 1](#f1) and [Figure 16](#f16).",
        "See [Figure 1](#f1).",
    );
    assert_eq!(uncited(&caption_only), vec![16]);
}

#[test]
fn a_rope_not_drawn_to_scale_has_an_exaggeration_above_one() {
    // A sagging rope, 9 m wide and 1.5 m deep, on a column-wide panel.
    let rope: Vec<(f64, f64)> = (0..10)
        .map(|i| (i as f64, -1.5 * (1.0 - ((i as f64 - 4.5) / 4.5).powi(2))))
        .collect();
    let mut p = Panel::new(Axis::linear("x (m)"), Axis::linear("y (m)"));
    p.series.push(Series::line("rope", rope, Rgb(0, 0, 0)));
    let stretched = layout(&Chart::new(COLUMN_WIDTH_MM, 70.0, vec![p.clone()])).unwrap();
    let e = scale::vertical_exaggeration(&stretched, 0);
    assert!(e > 2.0, "stretched: ×{e}");
    p.equal_aspect = true;
    let to_scale = layout(&Chart::new(COLUMN_WIDTH_MM, 70.0, vec![p])).unwrap();
    let e = scale::vertical_exaggeration(&to_scale, 0);
    assert!((e - 1.0).abs() < 1e-9, "to scale: ×{e}");
}

/// TIMING.md (written by `make timing`, committed): its figures in one sequence from 1, each
/// cited; the failing cases are those of the test above.
#[test]
fn the_timing_figures_are_numbered_in_one_sequence_and_each_is_cited() {
    let md = std::fs::read_to_string(crate_root().join("report/timing/TIMING.md")).unwrap();
    let problems = numbering::numbering_problems(&md, 1);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert_eq!(numbering::uncited(&md), Vec::<u32>::new());
}

/// An x tick label centred at the right end of the axes sticks out of the figure unless the
/// layout widens the right margin (a `timing --quick` wall-time figure did, under load).
#[test]
fn an_x_tick_label_at_the_right_end_stays_inside_the_figure() {
    // The axis ends at a labelled tick: "0.00020" is centred on the frame's right edge.
    let mut p = Panel::new(
        Axis::linear("wall time (s)").range(0.0, 2.0e-4),
        Axis::log("error (m)"),
    );
    let points: Vec<(f64, f64)> = (1..=9)
        .map(|i| (2.0e-5 * i as f64, 10f64.powi(-i)))
        .collect();
    p.series
        .push(Series::line("run", points, Rgb(0, 0, 0)).with_marker(Marker::Circle, true));
    let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
    assert!(found.is_empty(), "{found:#?}");
}
