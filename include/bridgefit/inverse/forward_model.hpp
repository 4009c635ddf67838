#pragma once
// Forward models behind one interface, shaped like a cost function: a failed
// run is a reported status, never an exception, so one bad evaluation never
// kills a long fit (STYLE habit 4).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::inverse {

// Which R the data holds: energy released per unit growth (an energy-method
// experiment, the model's R_energy) or the elastic-zone R of PHYSICS 3.
// kAsData: the model's own load-displacement record reduced by the data's
// method (a SimulationForwardModel with a reducer), so that methods with a
// calibration or an equivalent crack length compare like with like.
enum class RKind { kEnergy, kElasticZone, kAsData };
const char* RKindName(RKind kind);
RKind ParseRKind(const std::string& name);

// The end of a forward run's message when the law reaches steady state
// within too few of the model's crack-length steps (a load-displacement
// prediction refuses it): the model's element size is too coarse for the
// law, and a finer one resolves it (pipeline::RunFit retries there).
inline constexpr const char* kNotResolvedAtThisResolution = "not resolved at this resolution";

// The fitted parameters; delta_c = J_B / (k sigma_c) with k the shape area.
struct LawParameters {
  double sigma_c = 0.0;  // [Pa]
  double J_B = 0.0;      // [J/m^2]; 0 means no bridging
  double J_tip_c = 0.0;  // [J/m^2]
};

struct ForwardPrediction {
  RunStatus status = RunStatus::kOk;
  std::string message;
  std::vector<double> R;           // at the requested crack lengths [J/m^2]
  std::vector<double> delta_root;  // notch-root COD there [m]
  bool steady_state_reached = false;
  double steady_state_crack_length = NAN;  // [m]
  // kAsData only: the physical crack length and the elastic-zone R of the
  // model point behind each data point (the data's axis may be an
  // equivalent crack length), for steady state and the PHYSICS 7 bounds.
  std::vector<double> crack_length_physical;  // [m]
  std::vector<double> R_physical;             // [J/m^2]
  // Per point, 1 where it lies past the steady state of its own specimen
  // (a joint model of several specimens, inverse/joint.hpp); empty: the
  // points are compared with steady_state_crack_length.
  std::vector<char> past_steady_state;
  // PredictLoad only: the model's load at the data's displacements [N].
  std::vector<double> load;
  bool ok() const { return status == RunStatus::kOk; }
};

class ForwardModel {
 public:
  virtual ~ForwardModel() = default;
  virtual std::string Name() const = 0;
  // R (and delta_root) at `crack_lengths` [m] for a law of `shape` with `p`.
  virtual ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                                    const std::vector<double>& crack_lengths,
                                    RKind kind) const = 0;
  // The load at the load-point displacements `displacements` [m] of a test
  // record, on the model's own loading path (linear to initiation, then
  // growth), with the physical crack length, elastic-zone R and notch-root
  // COD there (crack_length_physical, R_physical, delta_root). The default:
  // a status saying the model has no load-displacement record.
  virtual ForwardPrediction PredictLoad(const laws::LawShape& shape, const LawParameters& p,
                                        const std::vector<double>& displacements) const;
};

// The analytic model: R(delta_root) of PHYSICS 3 with the small-scale
// bridging map delta_root(Delta a): the LEFM opening a distance Delta a
// behind the tip under the far-field J, delta = sqrt(32 J_ff Delta a / (pi E')),
// solved for self-consistency with J_ff = J_tip,c + W(delta_root). It ignores
// the closure of the opening by the tractions and the finite specimen, so it
// is an approximation for short zones; it is templated so Ceres can
// differentiate it (AnalyticR).
class AnalyticForwardModel final : public ForwardModel {
 public:
  AnalyticForwardModel(double effective_modulus, double initial_crack_length);
  std::string Name() const override { return "analytic"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override;
  double effective_modulus() const { return modulus_; }
  double initial_crack_length() const { return a0_; }

 private:
  double modulus_;
  double a0_;
};

// delta_root for crack growth `growth` (fixed-point iterations; templated).
template <class T>
T AnalyticDeltaRoot(const laws::LawT<T>& law, const T& J_tip_c, double growth,
                    double effective_modulus) {
  using std::sqrt;
  if (growth <= 0.0) return T(0.0);
  const double c = 32.0 * growth / (3.14159265358979323846 * effective_modulus);
  T delta = sqrt(T(c) * J_tip_c);
  for (int i = 0; i < 30; ++i) delta = sqrt(T(c) * (J_tip_c + law.Work(delta)));
  return delta;
}

// Any simulator that grows the crack and returns a SimulationResult (the
// reduced model, MPM): its R or R_energy is interpolated at the data's crack
// lengths. `simulate` gets the law (null for J_B = 0) and J_tip,c.
class SimulationForwardModel final : public ForwardModel {
 public:
  using Simulator = std::function<SimulationResult(const laws::BridgingLaw* law, double J_tip_c)>;
  SimulationForwardModel(std::string name, Simulator simulate);
  // For RKind::kAsData: reduces a simulation's load-displacement record with
  // the data's own method to (crack length, R), and says which simulation
  // point each R comes from.
  struct Reduced {
    std::vector<double> crack_length, R;
    std::vector<int> point;
  };
  using Reducer = std::function<Reduced(const SimulationResult& result)>;
  void SetReducer(Reducer reduce) { reduce_ = std::move(reduce); }
  // A compliance C_s [m/N] in series with the specimen at the load point (a
  // test machine's load train, hinges, the specimen's root): PredictLoad's
  // path is the model's (displacement + C_s P, P). 0 by default; Predict
  // (R against crack length) does not depend on it.
  void SetSeriesCompliance(double compliance) { series_compliance_ = compliance; }
  double series_compliance() const { return series_compliance_; }
  std::string Name() const override { return name_; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override;
  ForwardPrediction PredictLoad(const laws::LawShape& shape, const LawParameters& p,
                                const std::vector<double>& displacements) const override;
  // PredictLoad with `series_compliance` [m/N] in place of the model's own
  // (thread-safe: the model is not changed).
  ForwardPrediction PredictLoadInSeries(const laws::LawShape& shape, const LawParameters& p,
                                        const std::vector<double>& displacements,
                                        double series_compliance) const;

 private:
  // Runs the simulator for `p`; a failure is in the result's status.
  SimulationResult Simulate(const laws::LawShape& shape, const LawParameters& p) const;
  std::string name_;
  Simulator simulate_;
  Reducer reduce_;
  double series_compliance_ = 0.0;
};

}  // namespace bridgefit::inverse
