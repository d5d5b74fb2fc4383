//! Tilings: a W×H grid of tile slots, boundary conditions, and the selection
//! function that offers, for any empty slot of any partial tiling, exactly the
//! tiles that keep the tiling completable (paper §4).
//!
//! Fluxes and corners are independent: corner velocities only have to match
//! between the (up to four) slots meeting at a grid vertex, which is a local
//! check, while fluxes are coupled across the whole grid by conservation. The
//! flux constraints live in a [`Network`](crate::flow::Network) (one node per slot plus the outside,
//! one arc per grid edge) that always holds a feasible circulation; see
//! [`crate::flow`].
//!
//! Grid conventions: slot `(x, y)` has `x` to the right and `y` up. Vertical
//! edge `(x, y)` (`0 ≤ x ≤ W`) lies between slots `(x-1, y)` and `(x, y)` and
//! carries flux towards +x; horizontal edge `(x, y)` (`0 ≤ y ≤ H`) lies
//! between `(x, y-1)` and `(x, y)` and carries flux towards +y. Vertex
//! `(x, y)` is the lower-left corner of slot `(x, y)`.
//!
//! Where things are:
//!
//! | file | what |
//! |---|---|
//! | `conditions.rs` | [`Border`], [`Edge`], [`Conditions`], [`parse_mask`], [`TilingError`], the size limits |
//! | `grid.rs` | the [`Tiling`] state, slot/edge/vertex indexing, accessors |
//! | `network.rs` | [`Tiling::new`]: the flow network and corner conditions from the boundary conditions |
//! | `select.rs` | the selection function ([`Selection`], [`Tiling::select`]), placing and removing tiles |
//! | `fill.rs` | forced positions, the random scan-line fill, placing one drawn tile |
//! | `shortcuts.rs` | the fill's ladder and seam cycles (short flux moves) |
//! | `chooser.rs` | preference weights of a preferring fill |

mod chooser;
mod conditions;
mod fill;
mod grid;
mod network;
mod select;
mod shortcuts;

pub use conditions::{Border, Conditions, Edge, MAX_SIDE, MAX_SLOTS, TilingError, parse_mask};
pub use grid::Tiling;
pub use select::Selection;

#[cfg(test)]
mod tests;
