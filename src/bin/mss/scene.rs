//! The scene of a run and its time stepper.

use crate::cli::{Cli, SceneArg, DEFAULT_ROPE_STIFFNESS, MAX_ROPE_NODES, MAX_SHEET_SIDE};
use crate::failure::Failure;
use crate::output::{AppliedForces, GroundSummary};
use crate::settings::{check, check_memory, check_range, Settings};
use mass_spring_solvers::error::{shown, Error};
use mass_spring_solvers::integrators::time_stepper::TimeStepper;
use mass_spring_solvers::model::scene::{
    check_geometry, RopeParams, SheetParams, MIN_START_LENGTH_RATIO, SHEET_NODES_PER_SIDE,
    THESIS_GRAVITY, THESIS_NODES,
};
use mass_spring_solvers::model::system::{MassSpringSystem, Vec3};
use mass_spring_solvers::particles::scene_file::{self, SceneFile, LIMITS};
use mass_spring_solvers::particles::scenes::{ClothDropParams, ClothParams, PendulumParams};
use mass_spring_solvers::particles::ParticleSystem;
use mass_spring_solvers::solvers::budget::Shape;
use mass_spring_solvers::solvers::registry::{Builder, SolverSpec};

/// What a scene is made of: a plain mass-spring system (every method runs it), a scene file
/// (which may ask for the tutorial's forces) or a tutorial particle system (drag and ground:
/// the tutorial's integrators only).
pub(crate) enum Model {
    Springs(MassSpringSystem),
    File(SceneFile),
    Particles(ParticleSystem),
}

impl Model {
    pub(crate) fn system(&self) -> &MassSpringSystem {
        match self {
            Model::Springs(system) => system,
            Model::File(file) => &file.system,
            Model::Particles(particles) => particles.system(),
        }
    }

    /// The viscous drag of a scene file, N·s/m (the built-in scenes' drag is the tutorial's
    /// force objects', small beside their springs: not counted).
    pub(crate) fn drag(&self) -> f64 {
        match self {
            Model::File(file) => file.forces.drag,
            _ => 0.0,
        }
    }

    /// The system for the thesis's solvers, which model undamped springs and gravity only.
    pub(crate) fn springs_only(&self, scene: &str) -> Result<MassSpringSystem, Failure> {
        match self {
            Model::Springs(system) => Ok(system.clone()),
            Model::File(file) => {
                file.require_springs_and_gravity_only().map_err(|e| {
                    Failure::input(format!(
                        "{scene}: {e}; explicit_euler, symplectic_euler, rk4 and rk45 model it"
                    ))
                })?;
                Ok(file.system.clone())
            }
            Model::Particles(_) => Err(Failure::input(format!(
                "invalid --scene: {scene} (allowed with the thesis's solvers and with \
                 --compare-reference: thesis, rope, hanging_cloth or a scene file without drag, \
                 ground or spring damping; {scene} needs explicit_euler, symplectic_euler, rk4 or rk45)"
            ))),
        }
    }

    /// The tutorial's particle system of the scene.
    pub(crate) fn into_particles(self) -> Result<ParticleSystem, Failure> {
        Ok(match self {
            Model::Springs(system) => ParticleSystem::from_system(system),
            Model::File(file) => file.particle_system()?,
            Model::Particles(particles) => particles,
        })
    }
}

/// Builds the scene with the stiffness and gravity overrides, once its memory estimate for the
/// solver is known to fit (from the counts alone for the rope and the sheet, before anything of
/// their size is allocated).
pub(crate) fn build_scene(cli: &Cli, settings: &Settings) -> Result<Model, Failure> {
    let model = build_model(cli, settings)?;
    check_memory(cli, settings, Shape::of(model.system()), None)?;
    Ok(model)
}

fn build_model(cli: &Cli, settings: &Settings) -> Result<Model, Failure> {
    let g = cli.gravity;
    if let Some(path) = &cli.scene_file {
        let mut file = scene_file::load(path)?;
        if let Some(k) = cli.stiffness {
            file.system = file.system.with_stiffness(k)?;
        }
        if let Some(g) = g {
            file.system = file.system.with_gravity(Vec3::new(0.0, -g, 0.0))?;
        }
        return Ok(Model::File(file));
    }
    let k = cli.stiffness;
    Ok(match cli.scene {
        SceneArg::Thesis => {
            let mut rope = RopeParams::thesis(k.unwrap_or(DEFAULT_ROPE_STIFFNESS));
            rope.gravity = g.unwrap_or(THESIS_GRAVITY);
            Model::Springs(rope.build()?)
        }
        SceneArg::Sheet => {
            let n = match cli.n {
                Some(n) => check_range("--n", n, 3, MAX_SHEET_SIDE)?,
                None => SHEET_NODES_PER_SIDE,
            };
            let (nodes, cells) = ((n * n) as u64, ((n - 1) * (n - 1)) as u64);
            let shape = Shape {
                nodes,
                springs: 2 * (nodes - n as u64) + 2 * cells,
                // Node (i, j) is joined to (i + 1, j + 1): n + 1 apart.
                chain: n < 12,
            };
            check_memory(cli, settings, shape, None)?;
            let mut sheet = SheetParams::spec(n, k.unwrap_or(DEFAULT_ROPE_STIFFNESS));
            sheet.gravity = g.unwrap_or(THESIS_GRAVITY);
            Model::Springs(sheet.build()?)
        }
        SceneArg::Rope => {
            let mut rope = RopeParams::thesis(k.unwrap_or(DEFAULT_ROPE_STIFFNESS));
            rope.nodes = match cli.nodes {
                Some(n) => check_range("--nodes", n, 3, MAX_ROPE_NODES)?,
                None => THESIS_NODES,
            };
            let shape = Shape {
                nodes: rope.nodes as u64,
                springs: rope.nodes as u64 - 1,
                chain: true,
            };
            check_memory(cli, settings, shape, None)?;
            if let Some(l) = cli.rest_length {
                rope.rest_length = LIMITS.rest_length.check("--rest-length", l)?;
            }
            if let Some(m) = cli.node_mass {
                rope.node_mass = LIMITS.mass.check("--node-mass", m)?;
            }
            let span = match cli.span {
                Some(s) => {
                    let longest = LIMITS.coordinate.max;
                    check(
                        "--span",
                        s,
                        s > 0.0 && s <= longest,
                        &format!("a number > 0 and at most {}, in m", shown(longest)),
                    )?
                }
                None => (rope.nodes - 1) as f64 * rope.rest_length,
            };
            rope.anchor_right = rope.anchor_left + Vec3::new(span, 0.0, 0.0);
            rope.gravity = g.unwrap_or(THESIS_GRAVITY);
            let system = rope.build()?;
            check_geometry(&system).map_err(|_| {
                Error::invalid(
                    "--span",
                    shown(span),
                    &format!(
                        "a span of at least {} of (nodes - 1) × the rest length: shorter, every \
                         spring starts crushed to nothing",
                        shown(MIN_START_LENGTH_RATIO)
                    ),
                )
            })?;
            Model::Springs(system)
        }
        SceneArg::HangingCloth => {
            let defaults = ClothParams::default();
            let cloth = ClothParams {
                stiffness: k.unwrap_or(defaults.stiffness),
                // The thesis's solvers model undamped springs; every method runs the same scene.
                damping: 0.0,
                gravity: g.unwrap_or(defaults.gravity),
                ..defaults
            };
            Model::Springs(cloth.hanging()?)
        }
        SceneArg::ClothDrop => {
            let mut drop = ClothDropParams::tutorial();
            drop.cloth.stiffness = k.unwrap_or(drop.cloth.stiffness);
            drop.cloth.gravity = g.unwrap_or(drop.cloth.gravity);
            Model::Particles(drop.build()?)
        }
        SceneArg::Pendulum => {
            let mut pendulum = PendulumParams::tutorial();
            pendulum.stiffness = k.unwrap_or(pendulum.stiffness);
            pendulum.gravity = g.unwrap_or(pendulum.gravity);
            Model::Particles(pendulum.build()?)
        }
        // `run` solves these before any model is built (src/bin/mss/continuum.rs).
        SceneArg::Beam | SceneArg::Membrane | SceneArg::Cook | SceneArg::Patch => {
            return Err(Failure::input(format!(
                "--scene {} is a continuum scene: statics only, no time stepping",
                cli.scene.id()
            )))
        }
    })
}

/// The time stepper of `spec` on the scene, and the tutorial's force objects and ground it
/// applies (none for the solvers of springs and gravity).
pub(crate) fn build_stepper(
    spec: &SolverSpec,
    model: Model,
    scene: &str,
    dt: f64,
) -> Result<(Box<dyn TimeStepper>, Option<AppliedForces>), Failure> {
    Ok(match spec.id.info().builder {
        Builder::Springs(_) => (spec.build(&model.springs_only(scene)?, dt)?, None),
        Builder::Particles(_) => {
            let particles = model.into_particles()?;
            let applied = AppliedForces {
                forces: particles.forces().iter().map(|f| f.name()).collect(),
                ground: particles.ground().map(|g| GroundSummary {
                    height_m: g.height(),
                    restitution: g.restitution(),
                }),
            };
            (spec.build_particles(particles, dt)?, Some(applied))
        }
    })
}
