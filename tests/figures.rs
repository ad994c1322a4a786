//! The figure test on synthetic charts: it passes a clean chart and fails each defect it
//! guards against (a legend over data, a mark outside its axes, overlapping labels), so a
//! pass on the report's figures (`tests/report.rs`) means something.

mod figure_check;

use figure_check::problems;
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
    for place in [LegendPlace::Right, LegendPlace::Below] {
        let mut p = rising();
        p.legend = place;
        let found = check(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]));
        assert!(found.is_empty(), "{place:?}: {found:#?}");
    }
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
            .any(|f| f.contains("\"rising too\" and \"same look\" of panel 1 share colour")),
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
