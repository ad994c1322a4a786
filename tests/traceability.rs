//! Equation traceability: every numbered equation of the thesis (1-56) is implemented by a
//! tagged function or listed as a definition or derivation with its reason, and those that
//! must have code (1-4, 6-10, 12-14, 18-20, 24-29, 40-56) have it; every solver's step
//! function is marked for quoting. The snapshot holds the table without line numbers, so that
//! edits which only move code do not change it.

use mass_spring_report::crate_root;
use mass_spring_report::traceability::{
    missing, must_have_code, scan, solver_step, summary, NOT_CODE,
};
use mass_spring_solvers::solvers::registry::SolverId;

#[test]
fn every_equation_is_implemented_or_listed() {
    let tags = scan(&crate_root()).expect("src/ reads");
    let missing = missing(&tags);
    assert!(
        missing.is_empty(),
        "equations without code and not listed as a derivation or definition (or required to have code): {missing:?}\n{}",
        summary(&tags)
    );
}

#[test]
fn listed_equations_are_not_ones_that_need_code() {
    for (n, _, reason) in NOT_CODE {
        assert!(
            !must_have_code(n),
            "Eq. ({n}) must have code; it cannot be listed ({reason})"
        );
    }
}

#[test]
fn traceability_table_matches_its_snapshot() {
    let tags = scan(&crate_root()).expect("src/ reads");
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("traceability", summary(&tags));
    });
}

#[test]
fn every_solver_step_is_marked_for_quoting() {
    let root = crate_root();
    let problems: Vec<String> = SolverId::THESIS_TABLES
        .into_iter()
        .filter_map(|s| solver_step(&root, s).err().map(|e| e.to_string()))
        .collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The second table: every solver after the thesis cites its paper in its own module, with
/// tags the thesis's table cannot read as thesis equations.
#[test]
fn every_newer_solver_cites_its_paper() {
    use mass_spring_report::traceability::{parse_paper_tag, parse_tag, scan_papers};
    use mass_spring_solvers::solvers::registry::Family;
    let tags = scan_papers(&crate_root()).expect("src/ reads");
    for id in SolverId::ALL
        .into_iter()
        .filter(|id| id.info().family == Family::Beyond)
    {
        let file = id.info().file;
        assert!(
            tags.iter().any(|t| t.file == file),
            "{id}: no [Author Year, …] tag in {file}"
        );
    }
    assert_eq!(
        parse_paper_tag("[Wang 2015, Eq. 12] ω"),
        Some(("Wang 2015".into(), "Eq. 12".into()))
    );
    assert_eq!(parse_paper_tag("[`link`] text"), None);
    assert_eq!(parse_tag("[Wang 2015, Eq. 12] ω"), None);
}

/// Every `[Author Year, …]` tag is in the paper table, says how it was checked, and only the
/// works whose body could not be read have unverified tags; the snapshot keeps each tag (paper,
/// what, verification, item), so that a renumbered or dropped tag shows in review. What would
/// fail it: a tag of an unread paper whose doc line names no reference code, "unverified" on a
/// tag of a read text, or a tag of a work on neither list.
#[test]
fn every_paper_tag_says_how_it_was_verified() {
    use mass_spring_report::traceability::{
        paper_summary, paper_table, scan_papers, verification, Verified,
    };
    let tags = scan_papers(&crate_root()).expect("src/ reads");
    let table = paper_table(&tags).render();
    for tag in &tags {
        assert!(
            tag.verified.is_some(),
            "{}:{} [{}, {}]: the doc line does not say how it was checked",
            tag.file,
            tag.line,
            tag.paper,
            tag.reference
        );
        assert!(table.contains(&format!("`{}:{}`", tag.file, tag.line)));
    }
    assert_eq!(
        verification("Wang 2015", "[Wang 2015, Eq. 14] ω"),
        Some(Verified::Text)
    );
    assert_eq!(
        verification("Wang 2015", "[Wang 2015, Eq. 14] (unverified) ω"),
        None
    );
    assert_eq!(verification("Peng 2018", "[Peng 2018, Eq. 4] mixing"), None);
    assert_eq!(
        verification(
            "Peng 2018",
            "[Peng 2018, x] checked against bldeng/AASolver"
        ),
        Some(Verified::ReferenceCode)
    );
    assert_eq!(
        verification("Smith 2020", "[Smith 2020, x] checked against y"),
        None
    );
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("paper_tags", paper_summary(&tags));
    });
}
