#pragma once
// The forward models of a fit request (private to the pipeline).

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "bridgefit/inverse/forward_model.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/pipeline/fit.hpp"

namespace bridgefit::pipeline {

// The scene with every modulus scaled by `factor` (the compliance of an
// elastic model scales by 1 / factor).
Scene ScaledModuli(const Scene& scene, double factor);

// R kind as-data: the model's points become a record (a linear loading
// branch to initiation, then one row per crack length) that is reduced with
// the data's own method and options (`input.reduction_options`), without
// noise, and with the data's compliance calibration (`input.reduction`'s
// figures, where the record was reduced here).
inverse::SimulationForwardModel::Reducer ModelRecordReducer(const FitInput& input);

// Reduced models already built during one fit, by every input of their
// mesh at full precision: the resolution chooser, the fit and the model
// error ask for the same element sizes (a CT at 0.5 mm takes 0.07-0.1 s to
// build on two cores); a model is built once and shared read-only.
// Thread-safe.
class ReducedModelCache {
 public:
  std::shared_ptr<const models::ReducedModel> Get(const Scene& scene,
                                                  const specimen::CrackPlaneOptions& mesh);

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const models::ReducedModel>> models_;
};

// The request's forward model (and, for --model auto, the MPM check), built
// on the scene with its moduli x a factor and a compliance in series.
class FitModels {
 public:
  // `cache` (may be null): where reduced models are shared (FitRun::reduced_models).
  FitModels(const FitRequest& request, const FitInput& input, const inverse::FitData& data,
            bool load_fit, inverse::RKind kind, ReducedModelCache* cache = nullptr);
  // Rebuilds the models; earlier references to them become invalid.
  void Build(double modulus_factor, double series_compliance);
  const inverse::ForwardModel& model() const { return *model_; }
  const inverse::ForwardModel* accurate() const { return accurate_.get(); }
  double mpm_cell() const { return mpm_cell_; }  // [m], NaN without MPM
  // --model auto: MPM at another cell [m] becomes accurate().
  void UseMpmCell(double cell);
  // The reduced model's element size [m] (NaN for analytic or MPM alone).
  double resolution() const { return resolution_; }
  // The reduced model as model() is (same scene scaling, series compliance
  // and R kind) at another element size: the model error's coarser solves
  // (issue 17; --model auto: its reduced model). Null when model() is not
  // the reduced model or the mesh is not valid at that size.
  // `far_field` > 0: that far-field factor instead of the request's.
  std::unique_ptr<inverse::ForwardModel> ReducedAt(double resolution, double far_field = 0.0) const;
  // The MPM growth model as accurate() (or model() for --model mpm) is, at
  // another cell size [m]: --model auto's convergence check.
  std::unique_ptr<inverse::ForwardModel> MpmAt(double cell) const;
  double data_end() const { return data_end_; }  // [m]

 private:
  const FitRequest& request_;
  const FitInput& input_;
  inverse::RKind kind_;
  ReducedModelCache* cache_ = nullptr;
  double data_end_ = 0.0;  // [m], the crack length the models must grow past
  std::unique_ptr<inverse::ForwardModel> model_;
  std::unique_ptr<inverse::ForwardModel> accurate_;
  double mpm_cell_ = NAN;
  double resolution_ = NAN;
  double modulus_factor_ = 1.0, series_compliance_ = 0.0;
  // The reduced model of the request at element size `resolution`, grown
  // `margin` [m] past the data, its far field `far_field` x the default.
  std::unique_ptr<inverse::SimulationForwardModel> MakeReduced(const Scene& scene,
                                                               double resolution,
                                                               double margin,
                                                               double far_field) const;
};

// A load-displacement fit starts where the R-curve fit (quick, without
// profiles) of `data` ends; the start goes into `options.initial` (fit.cpp).
inverse::FitSummary StartFromRCurveFit(const inverse::ForwardModel& model,
                                       const laws::LawShape& shape, const inverse::FitData& data,
                                       inverse::FitOptions& options);

// `--law bilinear|trilinear|table` (fit_law.cpp): the family's shape fitted
// with the scale parameters (the table's N by AICc) into run.summary,
// run.shape and run.fitted_shape; data too few for every N it may try are
// an input error naming --law and the way out.
void FitShapeAlone(const FitRequest& request, const inverse::ForwardModel& model,
                   const inverse::FitData& fit_data, const inverse::FitOptions& options,
                   FitRun& run);
// A comparison row's fitted shape (empty for a fixed-shape family).
FittedShape FittedShapeOf(const inverse::LawComparison& c);
// The fitted shape's parameters as the summary prints them: each with its
// Wald 95% interval (1.96 se, the scale parameters free), said as such.
std::string FittedShapeText(const FittedShape& f, const inverse::FitSummary& s);

// --resolution auto (issue 17; fit_resolution.cpp): for the reduced model
// without a given element size, chooses one (inverse::ChooseResolution from
// a pilot fit at the coarsest valid size) and sets request.resolution and
// run.resolution_choice. Otherwise leaves both as they are.
void ChooseAutoResolution(FitRequest& request, const laws::LawShape& shape, FitRun& run);

// Every stage after the element size is known (fit.cpp): the models, the
// compliance calibration, the fit, the model error; `from` (optional): a
// fit's answer at another size to start the local search from.
void FitAtResolution(const FitRequest& request, FitRun& run,
                     const std::array<double, inverse::kParameterCount>* from = nullptr);

// After ChooseAutoResolution (fit_resolution.cpp): the fit at the chosen
// size, halved where the law is not resolved there (returns the sizes given
// up, "" for none), and halved again after the fit where its own model
// error shows in the data. `chosen`: the run as the choice left it.
std::string FitAtChosenSize(FitRequest& request, const FitRun& chosen, FitRun& run);
void RefineWhereTheErrorShows(FitRequest& request, const FitRun& chosen, FitRun& run);

// MPM's validity limits on its cell (fit_model_auto.cpp; docs/MPM.md): the
// coarsest cell [m] for a specimen whose data end at crack length
// `data_end` [m]: 2.5 mm at most, 8 cells through a DCB arm, 10 over the
// growth from the notch.
double CoarsestMpmCell(const SpecimenSpec& specimen, double data_end);
// The reasons an MPM cell [m] is too coarse for the request's specimen and
// the data's crack growth (mpm::GrowthCellTooCoarse, and 10 cells over the
// growth); empty when it is not. --model auto and --model mpm warn with it.
std::string MpmCellTooCoarse(const FitRequest& request, const FitModels& models, double cell);

// --model auto's fit (fit_model_auto.cpp): the reduced fit checked (and
// corrected) by MPM; with --mpm-cell auto (request.mpm_cell NaN) the cell
// is halved from models.mpm_cell() while MPM's own error at the final
// parameters (twice its R step to half the cell: order 1) is above half the
// tolerance, at most request.mpm_cell_halvings times; at a halved cell the
// step that led there is its error (order 1), so a finer run is made only
// when that is too large (run.mpm_cell_choice says how).
void FitCheckedByMpm(const FitRequest& request, FitModels& models, const inverse::FitData& data,
                     const inverse::FitOptions& options, FitRun& run);

// --model auto never passes silently (issue 17; fit_model_auto.cpp): after
// the checked fit, sets run.model_check_warning where the MPM check did not
// complete or its cell is too coarse for the scene, and accepts a
// correction to MPM only when MPM at half the cell agrees with itself
// better than with the reduced model; otherwise the reduced fit is reported.
// The model error of a fit corrected to MPM: MPM's own error at the data
// (run.mpm_error_R, order 1 from two cells) through a refit of the
// corrected model without it (inverse::CorrectedFitBias), F_s 3; not
// estimated, with the reason, when MPM's error is not known.
inverse::ModelErrorEstimate MpmCorrectionError(const FitModels& models,
                                               const inverse::FitData& data,
                                               const inverse::FitOptions& options,
                                               const FitRun& run);

void CheckModelAuto(const FitRequest& request, const FitModels& models,
                    const inverse::FitData& data, const inverse::FitOptions& options, FitRun& run);

}  // namespace bridgefit::pipeline
