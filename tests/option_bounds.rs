//! Issue 27's option-boundary test: every size option of `mss` at its maximum, under a 4 GiB
//! address-space limit, ends in exit 2 (refused before any allocation, by its range or by the
//! memory estimate) or in success: never in a signal (an abort on a failed allocation).
//! `timing`'s options are tested beside its other tests (`presentation/tests/timing_cli.rs`).

mod sandbox;
use sandbox::exits_2_or_succeeds;

/// The largest values the ranges in `mss --help` allow.
const MAX_SIDE: &str = "2000";
const MAX_NODES: &str = "10000000";
const MAX_HISTORY: &str = "100";
const MAX_WINDOW: &str = "20";
const I64_MAX: &str = "9223372036854775807";
const U32_MAX: &str = "4294967295";

#[test]
fn every_size_option_at_its_maximum_exits_2_or_succeeds_under_4_gib() {
    let mss = env!("CARGO_BIN_EXE_mss");
    let quick = ["--max-time", "0.01"];
    let cases: Vec<Vec<&str>> = vec![
        vec!["--scene", "sheet", "--n", MAX_SIDE],
        vec!["--scene", "sheet", "--n", MAX_SIDE, "--solver", "pbd"],
        vec!["--scene", "rope", "--nodes", MAX_NODES],
        vec!["--scene", "rope", "--nodes", MAX_NODES, "--solver", "pbd"],
        vec!["--solver", "lbfgs", "--history", MAX_HISTORY],
        vec!["--solver", "anderson_liu", "--window", MAX_WINDOW],
        vec!["--solver", "anderson_admm", "--window", MAX_WINDOW],
        vec!["--solver", "chebyshev_liu", "--warmup", U32_MAX],
        vec!["--iterations", I64_MAX],
        vec!["--positions-csv", "/dev/null", "--positions-every", I64_MAX],
        // One past the maximum: the range refuses it.
        vec!["--scene", "sheet", "--n", I64_MAX],
        vec!["--scene", "rope", "--nodes", I64_MAX],
        vec!["--solver", "lbfgs", "--history", U32_MAX],
    ];
    for case in &cases {
        exits_2_or_succeeds(mss, &[&case[..], &quick[..]].concat());
    }
}
