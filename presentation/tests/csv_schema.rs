//! Every data file of the committed report is a real CSV: read back with a strict reader (no
//! flexible records), its header as `report::schema` documents it, its column names
//! `name_unit`, and "none" written one way only, as an empty field. Negative cases: a line with
//! an unquoted comma, a header out of order and a `NaN` field are each rejected. The files of
//! `report/timing/` are read the same way, the committed ones and those of a `timing --quick`
//! run into a scratch directory.

use mass_spring_report::schema::{
    matches, schema_of, timing_schema_of, unit_suffix, FileSchema, TIMING_FILES,
};
use std::path::Path;

/// The problems of one file's text against its schema.
fn problems(name: &str, text: &str, schema: &FileSchema) -> Vec<String> {
    let mut out = Vec::new();
    let mut reader = csv::ReaderBuilder::new()
        .flexible(false)
        .from_reader(text.as_bytes());
    let header: Vec<String> = match reader.headers() {
        Ok(h) => h.iter().map(String::from).collect(),
        Err(e) => return vec![format!("{name}: no header: {e}")],
    };
    let expected: Vec<&str> = schema.columns.iter().map(|(n, _)| *n).collect();
    if header != expected {
        out.push(format!("{name}: header {header:?}, schema {expected:?}"));
    }
    for (column, unit) in schema.columns {
        let snake = column
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if !snake {
            out.push(format!("{name}: column {column} is not lower-case snake"));
        }
        if !unit.is_empty() && !schema.published_names && !column.ends_with(&unit_suffix(unit)) {
            out.push(format!(
                "{name}: column {column} does not end in its unit {unit}"
            ));
        }
    }
    for (i, record) in reader.records().enumerate() {
        match record {
            Err(e) => {
                out.push(format!("{name}: record {}: {e}", i + 2));
                break;
            }
            Ok(r) => {
                if let Some(f) = r
                    .iter()
                    .find(|f| ["none", "NaN", "nan", "inf", "-", "–"].contains(f))
                {
                    out.push(format!(
                        "{name}: record {}: field {f:?} (none is empty)",
                        i + 2
                    ));
                    break;
                }
            }
        }
    }
    out
}

/// The problems of every CSV of `dir` against `schema_of`, and how many files were read.
fn check_dir(
    dir: &Path,
    schema_of: fn(&str) -> Option<&'static FileSchema>,
) -> (usize, Vec<String>) {
    let mut all = Vec::new();
    let mut files = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !name.ends_with(".csv") {
            continue;
        }
        files += 1;
        match schema_of(&name) {
            None => all.push(format!("{name}: no schema in report::schema")),
            Some(schema) => all.extend(problems(
                &name,
                &std::fs::read_to_string(&path).unwrap(),
                schema,
            )),
        }
    }
    (files, all)
}

#[test]
fn every_data_file_reads_back_against_its_schema() {
    let data = mass_spring_report::crate_root().join("report/data");
    let (files, all) = check_dir(&data, schema_of);
    assert!(files > 30, "{files} files");
    assert!(all.is_empty(), "{}", all.join("\n"));
}

#[test]
fn every_committed_timing_file_reads_back_against_its_schema() {
    let timing = mass_spring_report::crate_root().join("report/timing");
    let (files, all) = check_dir(&timing, timing_schema_of);
    assert_eq!(files, TIMING_FILES.len(), "one file per schema");
    assert!(all.is_empty(), "{}", all.join("\n"));
}

/// `timing --quick` into a scratch directory: the files it writes read back too.
#[test]
fn a_quick_timing_run_writes_files_that_read_back() {
    let dir = std::env::temp_dir().join(format!("csv-schema-timing-{}", std::process::id()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_timing"))
        .args(["--quick", "--out", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (files, all) = check_dir(&dir, timing_schema_of);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(files >= 2, "{files} files");
    assert!(all.is_empty(), "{}", all.join("\n"));
}

#[test]
fn the_checks_reject_what_they_should() {
    let schema = schema_of("catenary.csv").unwrap();
    let good = "stiffness_n_per_m,node,x_m,y_m\n1000.0,0,0.0,0.0\n";
    assert!(problems("catenary.csv", good, schema).is_empty());
    let comma = "stiffness_n_per_m,node,x_m,y_m\n1000.0,0,0.0,0.0,extra\n";
    assert!(!problems("catenary.csv", comma, schema).is_empty());
    let order = "node,stiffness_n_per_m,x_m,y_m\n0,1000.0,0.0,0.0\n";
    assert!(!problems("catenary.csv", order, schema).is_empty());
    let nan = "stiffness_n_per_m,node,x_m,y_m\n1000.0,0,NaN,0.0\n";
    assert!(!problems("catenary.csv", nan, schema).is_empty());
    assert!(matches(
        "fig1[45]-kinetic-energy-*.csv",
        "fig14-kinetic-energy-k1e6-dt0.01.csv"
    ));
    assert!(!matches(
        "fig1[45]-kinetic-energy-*.csv",
        "fig13-kinetic-energy-x.csv"
    ));
    assert_eq!(unit_suffix("N/m"), "_n_per_m");
    assert_eq!(unit_suffix("1/s"), "_per_s");
}
