#pragma once
// The exponential integrator (Method::exponential): ETD2 (Cox and Matthews' exponential Runge–Kutta of
// order 2) on each smooth piece of the plant. With A the Jacobian of the piece the state is on,
// E = e^{hA}, P = ∫₀^h e^{sA} ds and Q = ∫₀^h e^{(h−s)A}·s ds:
//   a = y + P·f(y),   y ← a + (Q/h)·(f(a) − E·f(y))
// exact while the equations are linear (strings taut, the grip where A was taken, the duty held for the
// tick) and second order otherwise, the change of the nonlinear remainder over the step taken as linear.
// A (and E, P, Q) is kept while the system's linearisation_drift() from where it was taken stays below 1,
// and taken again where the state has settled if it stays more than a tenth of that away for 20 ms; the
// linearisations of several pieces and poses are cached, a vibrating grip revisiting the same ones. A
// moving state's new one is taken ahead of it along its last step's motion (the system's
// linearisation_lead()), so that it serves the way ahead as well as the state. A step
// that carried the state more than twice that far (a grip being moved) is taken again on a linearisation
// at its midpoint, about which the remainder's change is symmetric; while the grip goes on being carried,
// each step is linearised at the midpoint its predecessor's motion predicts, and taken again only where
// the prediction missed by more than the reach. Any other whole step whose second-stage
// correction (the remainder's change over it) exceeds a hundredth of a state's scale is taken again as two
// halves.
//
// Switches inside a step are located: the piece's switch functions are predicted along the step at
// kCheckpoints points from their linearisation; a step over which the piece changes is taken instead as
// kCheckpoints sub-steps, those in which a switch falls as finer ones, each on the piece its start is on.
// A sub-step on a piece with no linearisation within reach is taken as finer ones too (explicit
// Runge–Kutta where no linearisation is near), the piece linearised only when missed there a second
// time: a carried grip passes most of its pieces by.
//
// A system that has coordinates in which it is nearer linear (OdeSystem::to_linear: the plant's string
// stretches) is stepped in them, every cached linearisation and kept start with it.
#include <memory>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

std::unique_ptr<Integrator> make_exponential_integrator();

}  // namespace hmp::sim::plant
