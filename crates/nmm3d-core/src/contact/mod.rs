//! Contact between blocks: warning, detection on the current geometry, transfer of contact
//! state, penalty springs, Coulomb friction with cohesion and tensile strength, in-situ stress
//! as joint traction, and the open–close state rules (thesis Part 3; DDA, Shi 1988; the state
//! rules of ntdda `df22`).
//!
//! Per step the candidate pairs of pieces come from the warning list ([`broad`]); each pair is
//! detected on the current geometry (one plane per pair of pieces, `nmm3d_geom::contact`). A
//! new point inherits state, shear history, in-situ preload and bond from the previous step's
//! point of the same block pair nearest to it (within the transfer distance), else starts locked
//! with zero shear and no bond. Within the step the open–close iteration solves with the
//! springs of the current states and updates the states until none changes. With the force on
//! A split into N = n·f (compression positive) and the tangential part F_t:
//!
//! | state | force on A | leaves when |
//! |---|---|---|
//! | open | none | the gap closes (→ stick) |
//! | stick | P − k_n g n − k_s s | N < −T A (→ open); \|F_t\| > N tan φ + c A (→ slide) |
//! | slide | (n·P) n − k_n g n − N tan φ ŝ | N < −T A (→ open); the slip reverses (→ stick) |
//!
//! P is the in-situ preload σ₀·(−n) A of a point touching at the start, g the gap, s the
//! shear-spring extension, ŝ the slip direction, A the point's share of the contact area,
//! c and T the joint's cohesion and tensile strength. A bond (c, T) exists only for points
//! touching at the start and is lost for good when the point slides or opens; the preload is
//! lost when it opens.
//!
//! One concept per file: [`record`] (a point and its identity), [`transfer`] (what a new point
//! inherits), [`joint_force`] (what a joint pair found again keeps), [`rules`] (the open–close
//! state rules), [`penalty`] (springs), [`friction`] (Coulomb friction), [`assemble`] (the
//! contact terms of the system), [`detect`] (the detection driver), [`travel`] (which pairs
//! need detecting again), [`history`] (all points of a run, the contact part of the run's state,
//! and what the stepper asks of them), [`set`] (the surfaces they are detected on), on the
//! surfaces of [`surface`] and the material points of [`point`].

pub mod assemble;
pub mod broad;
pub mod damping;
pub mod detect;
pub mod facets;
pub mod friction;
pub mod history;
pub mod joint_force;
pub mod overlap_bound;
pub mod penalty;
pub mod point;
pub mod record;
pub mod rules;
pub mod set;
pub mod surface;
pub mod transfer;
pub mod travel;

pub use assemble::pair_clique;
pub use history::ContactHistory;
pub use record::{ContactParams, ContactRecord, ContactState, Strength};
pub use set::{overlap_problems, ContactSurfaces, ContactTimes};
