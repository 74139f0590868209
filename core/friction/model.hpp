// gmslab core: the one shape shared by every friction model.
//
// A model is described by a ModelInfo (registry entry): its JSON tag, its scalar parameters and,
// for multi-element models (Maxwell-slip, Leuven, GMS), the columns of its element table. Every
// parameter carries its symbol in the paper, its SI unit, its allowed range and a one-line meaning,
// so the JSON loader, the UI editor, the identification and the documentation all read the same
// table.
//
// The parameter values live in ModelParams, a copyable value type (presets, undo and A/B
// comparison come for free). build_model() validates a ModelParams and compiles it into an
// immutable FrictionModel; all changing values live in a separate flat state vector.
//
// Time stepping contract (see FrictionModel::step): over one step of length h the sliding velocity
// v is frozen, the model advances its state exactly (or as accurately as its equations allow) and
// returns the friction force that acts on the body during the next velocity update.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gmslab {

struct ParamSpec {
  std::string_view key;     // JSON key and identifier, e.g. "Fs"
  std::string_view symbol;  // symbol used in the paper, e.g. "F_s"
  std::string_view unit;    // SI unit, e.g. "N", "m/s", "N s/m", "-" for dimensionless
  std::string_view help;    // one-line meaning, shown as tooltip and in errors
  double lo;                // smallest allowed value
  double hi;                // largest allowed value
  bool lo_open = false;     // true: value must be > lo (not >=)
  bool log_scale = false;   // positive quantity spanning decades (UI sliders, identification)
  bool allowed(double x) const;
  std::string range_text() const;  // e.g. "(0, 1e+06] N"
};

// Parameter values of one model, in the order of its ModelInfo tables.
struct ModelParams {
  std::string model;                          // registry tag, e.g. "gms"
  std::vector<double> scalars;                // one per ModelInfo::scalars
  std::vector<std::vector<double>> elements;  // rows; one value per ModelInfo::columns

  // scalar, set_scalar, column: throw InputError naming the model's keys for an unknown key.
  double scalar(std::string_view key) const;
  void set_scalar(std::string_view key, double value);
  std::vector<double> column(std::string_view key) const;
  bool operator==(const ModelParams&) const = default;
};

// Inputs of one friction step.
struct FrictionInput {
  double v = 0.0;        // sliding velocity, frozen over the step [m/s]
  double h = 0.0;        // step length [s], > 0
  double f_other = 0.0;  // sum of all non-friction forces on the body [N] (stick band models)
  double mass = 0.0;     // mass of the body [kg]; 0 when the motion is prescribed
};

// What the UI and the trace show of one element of a multi-element model.
struct ElementState {
  double force = 0.0;     // element force F_i [N]
  bool slipping = false;  // false = stick (elastic), true = slip
};

class ModelInfo;

class FrictionModel {
 public:
  virtual ~FrictionModel() = default;
  virtual const ModelInfo& info() const = 0;
  virtual const ModelParams& params() const = 0;

  virtual std::size_t state_size() const = 0;
  // Virgin state: no deformation, all elements sticking, zero force at rest.
  virtual void reset(std::span<double> state) const = 0;
  // Advance the state over in.h with in.v frozen; return the friction force [N] (opposing motion
  // when positive v gives positive force: the force the surface exerts is minus this value).
  virtual double step(std::span<double> state, const FrictionInput& in) const = 0;
  // Steady-state (static) curve F_ss(v) [N], viscous part included.
  virtual double steady_state(double v) const = 0;
  // Largest non-viscous force the model can produce (break-away level) [N].
  virtual double break_away() const = 0;

  virtual std::size_t element_count() const { return 0; }
  virtual ElementState element(std::span<const double> /*state*/, std::size_t /*i*/) const {
    return {};
  }
};

class ModelInfo {
 public:
  std::string_view tag;       // JSON tag, e.g. "gms"
  std::string_view name;      // display name, e.g. "Generalized Maxwell-slip"
  std::string_view citation;  // where the equations come from
  std::string_view equation;  // the equations, one short plain-text paragraph
  std::vector<ParamSpec> scalars;
  std::vector<ParamSpec> columns;  // element table columns (empty: no elements)
  std::size_t min_elements = 0;
  std::size_t max_elements = 0;
  std::function<ModelParams()> defaults;
  // Cross-field checks (beyond each value's range); append one message per problem.
  std::function<void(const ModelParams&, std::vector<std::string>&)> check;
  std::function<std::unique_ptr<FrictionModel>(const ModelParams&)> build;

  std::ptrdiff_t scalar_index(std::string_view key) const;  // -1 if absent
  std::ptrdiff_t column_index(std::string_view key) const;  // -1 if absent
};

// All models, in display order.
const std::vector<ModelInfo>& model_registry();
// Throws InputError naming the known tags when tag is unknown.
const ModelInfo& model_info(std::string_view tag);

// Common base of the models whose state is one number (a bristle or spring deflection z [m]), zero
// in the virgin state (Dahl, LuGre, elasto-plastic): keeps the parameters and finds the registry
// entry by the parameters' model tag.
class SingleStateModel : public FrictionModel {
 public:
  const ModelInfo& info() const override { return model_info(params_.model); }
  const ModelParams& params() const override { return params_; }
  std::size_t state_size() const override { return 1; }
  void reset(std::span<double> state) const override { state[0] = 0.0; }

 protected:
  explicit SingleStateModel(const ModelParams& p) : params_(p) {}
  ModelParams params_;
};
// Every problem of p (shape, ranges, cross-field), each naming the parameter and allowed range;
// empty when p is valid. `where` prefixes each message (e.g. "friction").
std::vector<std::string> validate(const ModelParams& p, std::string_view where = "friction");
// Validates (throws InputError listing all problems) and compiles.
std::unique_ptr<FrictionModel> build_model(const ModelParams& p);

}  // namespace gmslab
