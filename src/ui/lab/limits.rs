//! The numbers the lab holds itself to: how much real time a frame may step, the
//! ranges the panel offers, when anti-aliasing goes off, the mouse spring, the
//! energy history's length. A leaf: it imports nothing of the lab.

use std::time::Duration;

/// Real time one frame may add to the physics (s): after a stall the rest is dropped
/// instead of running hundreds of catch-up steps.
pub const MAX_FRAME_TIME: f64 = 0.1;
/// Most physics steps one frame may run.
pub const MAX_STEPS_PER_FRAME: u32 = 64;
/// Wall time one frame may spend stepping the physics. A frame runs at least one step,
/// and no further step that would take it past this budget (judged by the last step's
/// time); the simulated time it had no room for is dropped. A scene whose step takes
/// tens of milliseconds (the pile at 100,000 spheres) then runs slower than real time
/// but stays interactive, instead of spending ever longer frames catching up.
pub const PHYSICS_BUDGET: Duration = Duration::from_millis(25);
/// Above this many particles the lab turns 4x MSAA off (and back on when a smaller
/// scene follows, unless the user chose otherwise in between): on a software GPU it
/// nearly triples the cost of drawing a crowd (100,000 spheres: about 175 ms a frame
/// with it, 60 ms without, on lavapipe).
pub const MSAA_LIMIT: usize = 20_000;
/// How often the scene's read-outs are recomputed while it runs (s). Some measure
/// every particle (the pile's takes milliseconds at 100,000 spheres): too slow for
/// every frame, and nobody reads numbers that change 60 times a second.
pub const READOUT_INTERVAL: Duration = Duration::from_millis(250);
/// Simulated seconds the lab must have been still (every movable particle asleep, its
/// Compare copy's too) before it is at rest and stops drawing: the span of the energy
/// plot (`views::energy::PLOT_SECONDS`), longer than a trail lasts
/// (`Trails::LIFETIME`), so that neither is still changing on screen when the drawing
/// stops. `tests/window.rs` checks it against both.
pub const REST_DELAY: f64 = 10.0;
/// How often a window at rest steps its physics, without drawing (real time): the
/// clock keeps counting at the physics' own fixed steps, well within [`MAX_FRAME_TIME`]
/// so no time is dropped, and a world that wakes by itself is drawn within this.
pub const REST_TICK: Duration = Duration::from_millis(50);
/// Physics rates the panel offers (Hz).
pub const PHYSICS_RATE_RANGE: std::ops::RangeInclusive<f32> = 30.0..=1000.0;
/// Time scales the panel offers.
pub const TIME_SCALE_RANGE: std::ops::RangeInclusive<f32> = 0.05..=4.0;
/// Width over height of the 3D view the scenes' camera hints frame: a 1280x720 window
/// less the panel. Narrower views get the camera further back.
pub const FRAMING_ASPECT: f32 = 1.4;

/// The mouse spring's natural frequency (Hz): how quickly a dragged particle follows.
pub const MOUSE_HERTZ: f32 = 5.0;
/// The mouse spring's damping ratio: a little under critical, so it settles at once.
pub const MOUSE_DAMPING_RATIO: f32 = 0.7;
/// Most acceleration the mouse spring gives (m/s², about 15 g): enough to lift any
/// particle against the strongest gravity a scene offers, too little to fling one.
pub const MOUSE_MAX_ACCELERATION: f32 = 150.0;
/// Most acceleration the mouse spring gives the mass joined by links to the dragged
/// particle (m/s²). The links carry that pull, so it cannot fling anything; it is
/// what lets a hard drag tear cloth: a 1 kg cloth can be pulled with 600 N, while its
/// default links tear at 100 N, and a gentle drag (the spring's 987 N/m per kg over
/// 10 cm) stays below that.
pub const MOUSE_JOINED_ACCELERATION: f32 = 600.0;
/// Fastest a dragged particle moves the step a link tears it from what it pulled
/// (m/s): about a hand's speed, so a torn-off piece stays in the hand.
pub const MOUSE_TORN_SPEED: f32 = 5.0;

/// Longest force arrow (m); see [`Lab::force_scale`].
pub const LONGEST_FORCE_ARROW: f32 = 2.0;

/// Samples kept for the energy plot.
pub const HISTORY: usize = 600;

/// Arrow scales of the inspector's vectors: metres of arrow per m/s of velocity and per
/// m/s² of acceleration (force over mass).
pub const VELOCITY_ARROW: f32 = 0.25;
/// See [`VELOCITY_ARROW`].
pub const ACCELERATION_ARROW: f32 = 0.1;
/// Most physics steps one run may ask for: `simulate --steps`, and a link's `steps=N`.
pub const MAX_STEPS: u64 = 100_000_000;
