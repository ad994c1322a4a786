//! Figures 1-15 of the thesis, redrawn from our runs as SVG at their printed size, and the
//! parity figure of the 56 published rows; each with the CSV of the points it draws and a
//! caption that states every choice the thesis leaves open.
//!
//! Colours follow Table 8: Backward Euler black; XPBD blue, Fast m-s orange, ADMM green,
//! darker for fewer iterations. Published values are hollow markers on dashed lines, ours
//! filled markers on solid lines. The style itself (sizes, fonts, legends outside the data)
//! is [`crate::plot`]'s.

use crate::inputs::ReportData;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::solvers::registry::SolverId;

mod common;
mod motion;
mod parity;
mod rest_state;
mod scene;

pub use common::{decimate, row_class, Figure};
use motion::*;
pub use motion::{five_instants, FIGURE13_NODE, FIGURE13_WINDOW_S};
pub use parity::PARITY_FIGURE;
use parity::*;
use rest_state::*;
use scene::*;

/// Figures 1-15 and the parity figure, in order.
pub fn all(data: &ReportData) -> Result<Vec<Figure>> {
    let pd = [SolverId::FastMassSpring, SolverId::AdmmPd];
    let all3 = [SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd];
    let [six, eight] = rest_states_xpbd(data)?;
    Ok(vec![
        figure1(data)?,
        figure2(data)?,
        figure3()?,
        figure4()?,
        error_against_dt(data, 5, 1e3, &all3)?,
        six,
        error_against_dt(data, 7, 1e6, &all3)?,
        eight,
        error_against_dt(data, 9, 1e3, &pd)?,
        error_against_dt(data, 10, 1e6, &pd)?,
        figure11(&data.runs)?,
        figure12(&data.runs)?,
        figure13(&data.runs)?,
        kinetic_energy_middle(&data.runs, 14)?,
        kinetic_energy_middle(&data.runs, 15)?,
        parity(data)?,
    ])
}
