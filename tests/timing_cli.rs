//! `make timing`'s binary: bad input is named before anything runs, and one point is measured
//! in its own process and printed as one row (the scaling study itself takes a minute: run by
//! `make timing`, not here).

use std::process::Command;

fn timing(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_timing"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_input_is_named() {
    let (code, _, err) = timing(&["--point", "nope", "10"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--point SOLVER") && err.contains("fast_mass_spring"),
        "{err}"
    );
    let (code, _, err) = timing(&["--point", "fast_mass_spring", "ten"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--point N"), "{err}");
    for n in ["1", "2", "100000000"] {
        let (code, _, err) = timing(&["--point", "fast_mass_spring", n]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("sheet.nodes_per_side"), "{err}");
    }
    let dir = std::env::temp_dir().join(format!("timing-cli-{}", std::process::id()));
    let (code, _, err) = timing(&["--max-side", "5", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--max-side"), "{err}");
    assert!(
        !dir.exists(),
        "nothing is written before the input is checked"
    );
}

/// A point's row: the sheet's counts, a factor for Liu, times that are positive and finite.
#[test]
fn a_point_is_one_row_of_positive_times() {
    let (code, out, err) = timing(&["--point", "fast_mass_spring", "20"]);
    assert_eq!(code, 0, "{err}");
    let row: Vec<&str> = out.trim().split(',').collect();
    assert_eq!(row.len(), 21, "{out}");
    assert_eq!(&row[..4], ["fast_mass_spring", "20", "400", "1482"]);
    assert!(
        row[4].parse::<usize>().unwrap() > 1482,
        "the factor fills in: {out}"
    );
    for (i, v) in row.iter().enumerate().skip(5) {
        if let Ok(v) = v.parse::<f64>() {
            assert!(v.is_finite() && v >= 0.0, "column {i}: {v}");
        }
    }
    assert!(row[14].parse::<f64>().unwrap() > 0.0, "{out}");
}
