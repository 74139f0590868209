// gmslab core: the list of friction models, in display order. Add a model by adding its
// *_model_info() here.
#include "core/friction/dahl.hpp"
#include "core/friction/elastoplastic.hpp"
#include "core/friction/gms.hpp"
#include "core/friction/leuven.hpp"
#include "core/friction/lugre.hpp"
#include "core/friction/maxwell_slip.hpp"
#include "core/friction/model.hpp"
#include "core/friction/static_friction.hpp"

namespace gmslab {

const std::vector<ModelInfo>& model_registry() {
  static const std::vector<ModelInfo> registry = [] {
    std::vector<ModelInfo> r;
    r.push_back(gms_model_info());
    r.push_back(lugre_model_info());
    r.push_back(elastoplastic_model_info());
    r.push_back(maxwell_slip_model_info());
    r.push_back(leuven_model_info());
    r.push_back(dahl_model_info());
    r.push_back(stribeck_model_info());
    r.push_back(coulomb_model_info());
    return r;
  }();
  return registry;
}

}  // namespace gmslab
