#include "core/friction/param_specs.hpp"

#include <sstream>

namespace gmslab::specs {

std::string num(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

void check_fc_le_fs(const ModelParams& p, std::vector<std::string>& out) {
  if (p.scalar("Fc") > p.scalar("Fs"))
    out.push_back("Fc must not exceed Fs (Fc = " + num(p.scalar("Fc")) + " N, Fs = " +
                  num(p.scalar("Fs")) + " N)");
}

}  // namespace gmslab::specs
