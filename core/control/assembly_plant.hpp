// gmslab core/control: the linear plant of an assembled plant (core/sim/assembly.hpp), from a chosen
// drive to a chosen output, for the root-locus design on several bodies.
//
// Linearised as the one-body plant (scenario_plant.hpp), per contact:
//   presliding: every contact stuck - a spring sum k_i (+ sigma0) and a damper sum sigma_i (+ sigma1)
//               + sigma2 between its bodies;
//   sliding:    every contact sliding at v0 - a damper dF_ss/dv(v0) between its bodies.
// Then M x'' + C x' + K x = b u over the free bodies (prescribed bodies and drive points are fixed;
// a pull drive's spring and damper tie its body to ground), and
//   G(s) = e_out^T (M s^2 + C s + K)^-1 b,
// with u the force of a force drive [N] or the position of a pull drive's point [m]
// (b = k_p + c_p s), and the output x.BODY [m] or v.BODY [m/s] (times s). Numerator and denominator
// come from Cramer's rule, their coefficients from the determinants evaluated on a circle of the
// plant's largest modal frequency (inverse DFT), exact for these polynomial degrees up to rounding.
#pragma once

#include <string>

#include "core/control/scenario_plant.hpp"
#include "core/control/transfer_function.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab::control {

// Throws InputError naming the drive / output when the drive is not a force or pull drive, the
// output is not a position or velocity, or the regime's v0 <= 0 (0: default_sliding_velocity of
// each contact's model).
TransferFunction assembly_transfer_function(const Assembly& a, std::size_t drive, const std::string& output,
                                            Regime r, double sliding_velocity = 0.0);

}  // namespace gmslab::control
