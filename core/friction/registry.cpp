// gmslab core: the list of friction models. Add a model by adding its *_model_info() here.
#include "core/friction/gms.hpp"
#include "core/friction/model.hpp"

namespace gmslab {

const std::vector<ModelInfo>& model_registry() {
  static const std::vector<ModelInfo> registry = [] {
    std::vector<ModelInfo> r;
    r.push_back(gms_model_info());
    return r;
  }();
  return registry;
}

}  // namespace gmslab
