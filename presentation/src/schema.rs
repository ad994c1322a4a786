//! The data files of the report, documented once: each file's columns with their units, from
//! which the report's section on data files is generated and against which a test reads every
//! file back with a strict CSV reader (`presentation/tests/csv_schema.rs`).
//!
//! Conventions: column names are lower-case `name_unit` (`dt_s`, `x_m`, `stiffness_n_per_m`,
//! `energy_j`); a column without a unit is a count, an identifier or a ratio; an empty field
//! means "none" or "does not apply" (no `none`, `NaN` or dash); numbers are the shortest
//! decimal that reads back to the same double. `results.csv` and `table1.csv` keep the
//! published table's own column names.

/// One column: its name and its unit (empty for a count, an identifier or a ratio).
pub type Column = (&'static str, &'static str);

/// One data file (or a family of files sharing a pattern, `*` standing for any text).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FileSchema {
    pub pattern: &'static str,
    pub about: &'static str,
    pub columns: &'static [Column],
    /// The published table's names, kept as printed (no unit suffixes).
    pub published_names: bool,
}

const RESULTS: &[Column] = &[
    ("table", ""),
    ("solver", ""),
    ("dt_s", "s"),
    ("iterations", ""),
    ("stiffness", "N/m"),
    ("error", "m"),
    ("ke_peaks", ""),
    ("half_period_s", "s"),
    ("period_rel_error", ""),
    ("half_period_exact_s", "s"),
];

const ERROR_AGAINST_DT: &[Column] = &[
    ("solver", ""),
    ("iterations", ""),
    ("dt_s", "s"),
    ("error_published_m", "m"),
    ("error_ours_m", "m"),
];

const SHAPES: &[Column] = &[("series", ""), ("node", ""), ("x_m", "m"), ("y_m", "m")];

const WORK_PRECISION_FIGURE: &[Column] = &[
    ("solver", ""),
    ("integrator", ""),
    ("iterations", ""),
    ("dt_s", "s"),
    ("flops", ""),
    ("physical_rel", ""),
    ("panel", ""),
];

/// Every data file of `report/data/`.
pub const FILES: &[FileSchema] = &[
    FileSchema {
        pattern: "results.csv",
        about: "every published row run by the faithful configuration, in the published table's columns (`half_period_s` under the thesis convention) plus the exact convention's T/2",
        columns: RESULTS,
        published_names: true,
    },
    FileSchema {
        pattern: "table1.csv",
        about: "the same for Table 1",
        columns: RESULTS,
        published_names: true,
    },
    FileSchema {
        pattern: "catenary.csv",
        about: "the exact discrete-chain equilibrium of the thesis rope",
        columns: &[("stiffness_n_per_m", "N/m"), ("node", ""), ("x_m", "m"), ("y_m", "m")],
        published_names: false,
    },
    FileSchema {
        pattern: "reproduction.csv",
        about: "the evidence class of every published row, the configuration that produced our numbers, the choices it rests on and its twin (section 6)",
        columns: &[
            ("table", ""),
            ("solver", ""),
            ("dt_s", "s"),
            ("iterations", ""),
            ("stiffness_n_per_m", "N/m"),
            ("evidence", ""),
            ("configuration", ""),
            ("rests_on", ""),
            ("twin_of", ""),
            ("published_peaks", ""),
            ("our_peaks", ""),
            ("published_half_period_s", "s"),
            ("our_half_period_s", "s"),
            ("half_period_rel_dev", ""),
            ("marginal", ""),
            ("better_time_convention", ""),
            ("published_error_m", "m"),
            ("our_error_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "configurations.csv",
        about: "every run of Fast m-s's other first iterate and of the ADMM candidates (section 6)",
        columns: &[
            ("configuration", ""),
            ("table", ""),
            ("solver", ""),
            ("dt_s", "s"),
            ("iterations", ""),
            ("stiffness_n_per_m", "N/m"),
            ("outcome", ""),
            ("peaks", ""),
            ("half_period_s", "s"),
            ("half_period_rel_dev", ""),
            ("error_l1_m", "m"),
            ("error_m", "m"),
            ("last_peak_energy_j", "J"),
            ("hit_time_limit", ""),
            ("reproduces", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "liu_grid.csv",
        about: "every run of the Fast m-s hypothesis: each grid point on each Fast m-s row and the probes of the damping interval (appendix A.3)",
        columns: &[
            ("configuration", ""),
            ("role", ""),
            ("table", ""),
            ("dt_s", "s"),
            ("iterations", ""),
            ("stiffness_n_per_m", "N/m"),
            ("exempt_first_peak", ""),
            ("damping_per_s", "1/s"),
            ("threshold_j", "J"),
            ("peaks", ""),
            ("half_period_s", "s"),
            ("error_m", "m"),
            ("last_peak_energy_j", "J"),
            ("reproduces", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "gravity-mismatch.csv",
        about: "the gravity-mismatch errors (appendix A.5) against our reference runs and against the exact equilibria",
        columns: &[
            ("table", ""),
            ("solver", ""),
            ("dt_s", "s"),
            ("iterations", ""),
            ("stiffness_n_per_m", "N/m"),
            ("configuration", ""),
            ("published_error_m", "m"),
            ("error_same_gravity_m", "m"),
            ("error_l1_same_gravity_m", "m"),
            ("error_reference_9_8_m", "m"),
            ("error_l1_reference_9_8_m", "m"),
            ("error_solver_9_8_m", "m"),
            ("error_l1_solver_9_8_m", "m"),
            ("error_to_exact_same_gravity_m", "m"),
            ("error_to_exact_reference_9_8_m", "m"),
            ("error_to_exact_solver_9_8_m", "m"),
            ("solver_9_8_peaks", ""),
            ("solver_9_8_half_period_s", "s"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "parity.csv",
        about: "every published row with its class and the published and our peak count, T/2 and rest-state error (Figure P1)",
        columns: &[
            ("table", ""),
            ("solver", ""),
            ("dt_s", "s"),
            ("iterations", ""),
            ("stiffness_n_per_m", "N/m"),
            ("class", ""),
            ("peaks_published", ""),
            ("peaks_ours", ""),
            ("half_period_published_s", "s"),
            ("half_period_ours_s", "s"),
            ("error_published_m", "m"),
            ("error_ours_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "fig01-cloth.csv",
        about: "the sheet's nodes at each instant of Figure 1",
        columns: &[
            ("time_s", "s"),
            ("i", ""),
            ("j", ""),
            ("x_m", "m"),
            ("y_m", "m"),
            ("z_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "fig02-catenary.csv",
        about: "the shapes of Figure 2",
        columns: SHAPES,
        published_names: false,
    },
    FileSchema {
        pattern: "fig03-rope-structure.csv",
        about: "the springs and nodes of Figure 3",
        columns: &[
            ("element", ""),
            ("index", ""),
            ("x_a_m", "m"),
            ("y_a_m", "m"),
            ("x_b_m", "m"),
            ("y_b_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "fig04-distance-constraint.csv",
        about: "the points and gradients of Figure 4",
        columns: &[("quantity", ""), ("x_m", "m"), ("y_m", "m")],
        published_names: false,
    },
    FileSchema {
        pattern: "fig05-error-dt-k1e3.csv",
        about: "the points of Figure 5",
        columns: ERROR_AGAINST_DT,
        published_names: false,
    },
    FileSchema {
        pattern: "fig06-rest-state-xpbd-k1e3.csv",
        about: "the rest states of Figure 6",
        columns: SHAPES,
        published_names: false,
    },
    FileSchema {
        pattern: "fig07-error-dt-k1e6.csv",
        about: "the points of Figure 7",
        columns: ERROR_AGAINST_DT,
        published_names: false,
    },
    FileSchema {
        pattern: "fig08-rest-state-xpbd-k1e6.csv",
        about: "the rest states of Figure 8",
        columns: SHAPES,
        published_names: false,
    },
    FileSchema {
        pattern: "fig09-error-dt-k1e3-pd.csv",
        about: "the points of Figure 9",
        columns: ERROR_AGAINST_DT,
        published_names: false,
    },
    FileSchema {
        pattern: "fig10-error-dt-k1e6-pd.csv",
        about: "the points of Figure 10",
        columns: ERROR_AGAINST_DT,
        published_names: false,
    },
    FileSchema {
        pattern: "fig11-kinetic-energy-reference.csv",
        about: "the kinetic energy and its peaks in Figure 11 (long series reduced to the minimum and maximum of each of at most 1500 buckets)",
        columns: &[("series", ""), ("time_s", "s"), ("value_j", "J")],
        published_names: false,
    },
    FileSchema {
        pattern: "fig12-energy-and-motion.csv",
        about: "the instants, energies and shapes of Figure 12",
        columns: &[
            ("instant", ""),
            ("time_s", "s"),
            ("kinetic_energy_j", "J"),
            ("node", ""),
            ("x_m", "m"),
            ("y_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "fig13-motion-be-vs-fms.csv",
        about: "the lowest node's height in Figure 13",
        columns: &[("series", ""), ("time_s", "s"), ("y_m", "m")],
        published_names: false,
    },
    FileSchema {
        pattern: "fig1[45]-kinetic-energy-*.csv",
        about: "the kinetic energies of Figures 14 and 15",
        columns: &[("series", ""), ("time_s", "s"), ("kinetic_energy_j", "J")],
        published_names: false,
    },
    FileSchema {
        pattern: "beyond_convergence.csv",
        about: "the points of Figure B1",
        columns: &[
            ("solver", ""),
            ("start", ""),
            ("iteration", ""),
            ("gap_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "convergence.csv",
        about: "the gap to the converged Backward Euler step after each iteration of one step, every iterative solver (section 10.3)",
        columns: &[
            ("solver", ""),
            ("configuration", ""),
            ("scene", ""),
            ("start", ""),
            ("stiffness_n_per_m", "N/m"),
            ("dt_s", "s"),
            ("iteration", ""),
            ("gap_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "sheet_equilibrium.csv",
        about: "the sheet's exact equilibrium at n = 10 and 20",
        columns: &[
            ("stiffness_n_per_m", "N/m"),
            ("n", ""),
            ("i", ""),
            ("j", ""),
            ("x_m", "m"),
            ("y_m", "m"),
            ("z_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "sheet_rest_states.csv",
        about: "the points of Figure S1",
        columns: &[
            ("stiffness_n_per_m", "N/m"),
            ("node", ""),
            ("x_m", "m"),
            ("y_m", "m"),
            ("z_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "continuum_energies.csv",
        about: "the points of the continuum's energies figure: the soft beam's axis at each energy's equilibrium",
        columns: &[("energy", ""), ("node", ""), ("x_m", "m"), ("y_m", "m")],
        published_names: false,
    },
    FileSchema {
        pattern: "continuum_cook.csv",
        about: "the points of the continuum's Cook figure: u_y at (48, 52) and at (48, 60) for each mesh N (Cook's units: E = 1, unit load)",
        columns: &[("n", ""), ("u_y_48_52", ""), ("u_y_48_60", "")],
        published_names: false,
    },
    FileSchema {
        pattern: "continuum_membrane_sheet.csv",
        about: "the points of the continuum's membrane figure: the centre lines of the spring sheet and of the stable neo-Hookean membrane at rest",
        columns: &[
            ("series", ""),
            ("stiffness_n_per_m", "N/m"),
            ("node", ""),
            ("x_m", "m"),
            ("y_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "benchmark.csv",
        about: "every run of the benchmark (section 12 and the views of sections 10-11), one row each with every metric; `kind` is dynamics or statics",
        columns: BENCHMARK_COLUMNS,
        published_names: false,
    },
    FileSchema {
        pattern: "benchmark_own_start.csv",
        about: "the benchmark's own-start variant (section 12.4): the solvers whose own start is not the inertial prediction, from their own, with the columns of benchmark.csv",
        columns: BENCHMARK_COLUMNS,
        published_names: false,
    },
    FileSchema {
        pattern: "benchmark_references.csv",
        about: "the solver-error references per case, method and time step, with the fraction of their steps that reached the cap and the residual they reached (section 12.1)",
        columns: &[
            ("scene", ""),
            ("stiffness_n_per_m", "N/m"),
            ("method", ""),
            ("dt_s", "s"),
            ("capped_fraction", ""),
            ("target_residual_m", "m"),
            ("largest_end_residual_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "benchmark_thesis_protocol.csv",
        about: "reading (a) of the thesis's question (section 12.6): the thesis's three solvers by its own protocol at its time steps (the runs of Tables 2-7) and at 1/24 and 1/60 s, with its three measured quantities",
        columns: &[
            ("stiffness_n_per_m", "N/m"),
            ("dt_s", "s"),
            ("solver", ""),
            ("iterations", ""),
            ("setting", ""),
            ("at_rest", ""),
            ("end_time_s", "s"),
            ("rest_error_m", "m"),
            ("peaks", ""),
            ("half_period_s", "s"),
            ("period_rel_error", ""),
            ("source", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "benchmark_truths.csv",
        about: "the benchmark's ground truths per case (section 12.1)",
        columns: &[
            ("scene", ""),
            ("stiffness_n_per_m", "N/m"),
            ("linear_omega_rad_per_s", "rad/s"),
            ("exact_period_s", "s"),
            ("window_s", "s"),
            ("rk4_stability_limit_s", "s"),
            ("rk4_step_s", "s"),
            ("halving_gap_m", "m"),
            ("amplitude_rms_m", "m"),
            ("exact_energy_decay_per_period", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "benchmark_*_k1e*.csv",
        about: "the fronts drawn in the work-precision figures of section 12.3",
        columns: WORK_PRECISION_FIGURE,
        published_names: false,
    },
    FileSchema {
        pattern: "integrators.csv",
        about: "each optimization integrator's measured order and damping per period (section 13)",
        columns: &[
            ("integrator", ""),
            ("case", ""),
            ("order", ""),
            ("damping_per_period", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "integrator_costs.csv",
        about: "each minimizing solver's cost per step under each integrator (section 13)",
        columns: &[
            ("solver", ""),
            ("integrator", ""),
            ("target_m", "m"),
            ("iterations_per_step", ""),
            ("flops_per_step", ""),
            ("capped_stages", ""),
            ("solver_error_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "integrator_orders.csv",
        about: "the points of the integrators' order figure (section 13)",
        columns: &[("integrator", ""), ("dt_s", "s"), ("error_m", "m")],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_adaptive.csv",
        about: "the adaptive step size study of section 9.5",
        columns: &[
            ("scene", ""),
            ("tolerance_m", "m"),
            ("error_m", "m"),
            ("accepted", ""),
            ("rejected_error", ""),
            ("rejected_contact", ""),
            ("evaluations", ""),
            ("smallest_step_s", "s"),
            ("largest_step_s", "s"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_bounces.csv",
        about: "the energy kept at each bounce (section 9.4)",
        columns: &[
            ("scheme", ""),
            ("bounce", ""),
            ("energy_kept", ""),
            ("restitution_squared", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_cloth_drop.csv",
        about: "the points of the cloth-drop figure (section 9.4)",
        columns: &[
            ("time_s", "s"),
            ("particle", ""),
            ("x_m", "m"),
            ("y_m", "m"),
            ("z_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_convergence.csv",
        about: "the convergence orders of section 9.1",
        columns: &[
            ("method", ""),
            ("zeta", ""),
            ("h_s", "s"),
            ("error_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_forces.csv",
        about: "each force against its closed form (section 9.3), in the study's own unit",
        columns: &[
            ("study", ""),
            ("time_s", "s"),
            ("ours", ""),
            ("closed_form", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_gravities.csv",
        about: "the several-gravities particles against their closed form (section 9.3)",
        columns: &[
            ("particle", ""),
            ("gravities", ""),
            ("x_m", "m"),
            ("y_m", "m"),
            ("z_m", "m"),
            ("closed_x_m", "m"),
            ("closed_y_m", "m"),
            ("closed_z_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_pendulum_energy.csv",
        about: "the pendulum's energy (section 9.4)",
        columns: &[
            ("series", ""),
            ("time_s", "s"),
            ("particle", ""),
            ("energy_j", "J"),
            ("energy_before_step_j", "J"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_pendulum_frames.csv",
        about: "the pendulum's frames (section 9.4)",
        columns: &[
            ("time_s", "s"),
            ("particle", ""),
            ("x_m", "m"),
            ("y_m", "m"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_stability.csv",
        about: "the stability limits of section 9.2",
        columns: &[
            ("integrator", ""),
            ("largest_stable_h_omega", ""),
            ("closed_form", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "tutorial_stability_energy.csv",
        about: "the energy ratios of section 9.2's figure",
        columns: &[
            ("integrator", ""),
            ("h_omega", ""),
            ("periods", ""),
            ("energy_ratio", ""),
        ],
        published_names: false,
    },
];

/// Every data file of `report/timing/`, written by `make timing` (`presentation/src/bin/timing/`) from
/// the serde rows of [`crate::benchmark::wall`] and the scaling study.
pub const TIMING_FILES: &[FileSchema] = &[
    FileSchema {
        pattern: "benchmark_wall.csv",
        about: "every dynamics configuration of the benchmark timed on one core, beside its flops and relative physical error",
        columns: &[
            ("scene", ""),
            ("stiffness_n_per_m", "N/m"),
            ("solver", ""),
            ("iterations", ""),
            ("integrator", ""),
            ("stopping", ""),
            ("dt_s", "s"),
            ("wall_s", "s"),
            ("cpu_s", "s"),
            ("wall_spread", ""),
            ("flagged", ""),
            ("flops", ""),
            ("physical_rel", ""),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "machine.csv",
        about: "who measured: the commit, the machine, when, the load and the run time",
        columns: &[
            ("commit", ""),
            ("uncommitted_changes", ""),
            ("cpu", ""),
            ("cores", ""),
            ("toolchain", ""),
            ("measured_utc", ""),
            ("load_before", ""),
            ("load_after", ""),
            ("run_time_s", "s"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "scaling.csv",
        about: "the sheet's scaling study: each solver's set-up, iteration and step times at each size",
        columns: &[
            ("solver", ""),
            ("n", ""),
            ("nodes", ""),
            ("springs", ""),
            ("factor_nnz", ""),
            ("setup_s", "s"),
            ("setup_cpu_s", "s"),
            ("setup_spread", ""),
            ("local_s", "s"),
            ("local_cpu_s", "s"),
            ("local_spread", ""),
            ("global_s", "s"),
            ("global_cpu_s", "s"),
            ("global_spread", ""),
            ("iteration_s", "s"),
            ("iteration_cpu_s", "s"),
            ("step_s", "s"),
            ("step_cpu_s", "s"),
            ("step_spread", ""),
            ("step_repeats", ""),
            ("peak_bytes", "bytes"),
        ],
        published_names: false,
    },
    FileSchema {
        pattern: "bandwidth.csv",
        about: "the read bandwidth at each size of Fast m-s's factor",
        columns: &[
            ("n", ""),
            ("factor_bytes", "bytes"),
            ("read_bandwidth_bytes_per_s", "bytes/s"),
        ],
        published_names: false,
    },
];

/// The schema of a file of `report/timing/`.
pub fn timing_schema_of(name: &str) -> Option<&'static FileSchema> {
    TIMING_FILES.iter().find(|f| matches(f.pattern, name))
}

/// Whether `name` matches `pattern`, `*` standing for any text and `[ab]` for one of its
/// characters.
pub fn matches(pattern: &str, name: &str) -> bool {
    fn go(p: &[u8], n: &[u8]) -> bool {
        match p.split_first() {
            None => n.is_empty(),
            Some((b'*', rest)) => (0..=n.len()).any(|i| go(rest, &n[i..])),
            Some((b'[', rest)) => {
                let close = rest.iter().position(|&c| c == b']').unwrap_or(rest.len());
                let (set, after) = rest.split_at(close);
                !n.is_empty() && set.contains(&n[0]) && go(&after[1.min(after.len())..], &n[1..])
            }
            Some((&c, rest)) => n.first() == Some(&c) && go(rest, &n[1..]),
        }
    }
    go(pattern.as_bytes(), name.as_bytes())
}

/// The schema of a data file, by its name in `report/data/`.
pub fn schema_of(name: &str) -> Option<&'static FileSchema> {
    FILES.iter().find(|f| matches(f.pattern, name))
}

/// The unit's suffix in a column name: `m` → `_m`, `N/m` → `_n_per_m`, `1/s` → `_per_s`.
pub fn unit_suffix(unit: &str) -> String {
    let unit = unit.to_lowercase();
    let unit = unit
        .strip_prefix("1/")
        .map_or(unit.clone(), |u| format!("per_{u}"));
    format!("_{}", unit.replace('/', "_per_"))
}

/// The report's section on data files, generated from [`FILES`].
pub fn section_list() -> String {
    let mut md = String::new();
    for f in FILES {
        let columns: Vec<&str> = f.columns.iter().map(|(name, _)| *name).collect();
        let link = if f.pattern.contains(['*', '[']) {
            format!("`data/{}`", f.pattern)
        } else {
            format!("[`data/{p}`](data/{p})", p = f.pattern)
        };
        md += &format!("- {link}: {}. Columns `{}`.\n", f.about, columns.join(","));
    }
    md
}

/// The columns of `benchmark.csv` and of its own-start variant.
const BENCHMARK_COLUMNS: &[(&str, &str)] = &[
    ("kind", ""),
    ("scene", ""),
    ("stiffness_n_per_m", "N/m"),
    ("solver", ""),
    ("iterations", ""),
    ("integrator", ""),
    ("stopping", ""),
    ("first_iterate", ""),
    ("start_distance_m", "m"),
    ("dt_s", "s"),
    ("window_s", "s"),
    ("flops", ""),
    ("dt_over_stability_limit", ""),
    ("iterations_mean", ""),
    ("solver_error_target_m", "m"),
    ("capped_fraction", ""),
    ("physical_rms_m", "m"),
    ("physical_max_m", "m"),
    ("physical_rel", ""),
    ("reference_capped_fraction", ""),
    ("solver_rms_m", "m"),
    ("solver_max_m", "m"),
    ("solver_rel", ""),
    ("phase_error", ""),
    ("energy_decay_per_period", ""),
    ("exact_energy_decay_per_period", ""),
    ("at_rest", ""),
    ("end_time_s", "s"),
    ("rest_error_rms_m", "m"),
    ("peaks", ""),
    ("half_period_s", "s"),
    ("failure", ""),
];
