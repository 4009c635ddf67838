#pragma once
// Experiment design from a fit (issue 19): `bridgefit design FIT.h5` (or a
// campaign.h5). The fitted law and the specimen it was fitted on are read
// from the file (pipeline::ReadFittedLaw, campaign::ReadCampaignLaw); the
// design (campaign::RunDesign, the reduced model over similar specimens) is
// run for
//   - the bound law: sigma_c at its fitted value, J_B at its lower bound
//     (PHYSICS 7) when the fit reports a bound, else at its value;
//   - every law of the fit's region, a grid x grid lattice over
//       sigma_c in its total 95% interval (an open or zero end - sigma_c
//       -> 0 would need an infinite specimen - replaced by value / span or
//       value x span, `sigma_c_span`, stated),
//       J_B in its 95% interval when identified, else from the lower bound
//       up to a stated cap: jb_cap_factor x the bound (the data give no
//       upper end; the cap is the design's assumption and is reported);
//     delta_c follows from the shape: J_B = k sigma_c delta_c.
// Per size: the onset for the bound law, the latest onset over the region
// (the worst case) and whether every law of the region identifies J_B
// (campaign/design.hpp's rule). The smallest size for the bound law and for
// the whole region are the answers ("none in the range" when -1).

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bridgefit/campaign/design.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/report/design_chart.hpp"

namespace bridgefit::campaign {

struct FitDesignRequest {
  pipeline::FittedLaw law;  // from ReadDesignLaw
  // The specimen to design: empty, or it must be the fit's own (a CT fit
  // designs CTs; another shape needs `scene`).
  std::optional<SpecimenType> specimen;
  // Optional: the shape (specimen and material) to design instead of the
  // fit's own specimen; its law and fracture are replaced by the fit's.
  std::optional<Scene> scene;
  std::vector<double> sizes;         // [m], ascending: CT W, DCB L
  int grid = 3;                      // region points per parameter (>= 2: the corners)
  double jb_cap_factor = 2.0;        // J_B's upper end when only a bound is known
  double sigma_c_span = 2.0;         // sigma_c's end where its interval is open or zero
  double resolution_fraction = 0.0;  // as DesignRequest
  int r_points = 20;
  int points_past_onset = 3;
  bool IsValid(std::string* why) const;
};

struct RegionLaw {
  double sigma_c = NAN, J_B = NAN, delta_c = NAN;  // [Pa], [J/m^2], [m]
};

struct FitDesignSize {
  double size = 0.0, notch = 0.0, window_end = 0.0;  // [m] (the bound law's run)
  double bound_onset = NAN;                          // [m]; NaN: not reached
  bool bound_identifies = false;
  double worst_onset = NAN;  // latest onset over the region [m]; NaN: some law not reached
  int worst_law = -1;        // index in `region` of the worst case (latest or not reached)
  int region_reached = 0;    // laws of the region that reach steady state
  int region_identify = 0;   // ... and identify J_B
  int region_unknown = 0;    // ... whose model run stopped early
  double min_onset = NAN, max_onset = NAN;  // over the laws that reached [m]
};

struct FitDesignResult {
  std::string source, note;  // the file and where its law came from
  SpecimenType specimen = SpecimenType::kCT;
  RegionLaw bound;
  std::vector<RegionLaw> region;
  std::string bound_text, region_text;  // how each was chosen, with units
  std::vector<FitDesignSize> sizes;
  DesignResult bound_design;                 // the bound law's design
  std::vector<DesignResult> region_designs;  // one per region law
  int smallest_bound = -1;                   // index into sizes; -1: none in the range
  int smallest_region = -1;                  // every law of the region identifies
  double wall_s = 0.0;
  std::string Warning() const;
  std::string BriefReport() const;
};

// The law of a fit file or a campaign.h5 (told apart by its /campaign
// group). Throws Error(kInput) naming the file and what is expected.
pipeline::FittedLaw ReadDesignLaw(const std::filesystem::path& path);

// The scene the design runs for a law: the fit's specimen and material (or
// request.scene's) with the fit's J_tip,c and the law `law`.
Scene DesignScene(const FitDesignRequest& request, const RegionLaw& law);

// The bound law and the region's lattice (bound_text, region_text say how).
void ChooseLaws(const FitDesignRequest& request, FitDesignResult* result);

FitDesignResult RunFitDesign(const FitDesignRequest& request);

// The chart's view of a design (report::WriteDesignChart draws it).
report::DesignChartView DesignChartOf(const FitDesignResult& result);

}  // namespace bridgefit::campaign
