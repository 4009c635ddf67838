#pragma once
// HTML report of a campaign (issue 19): index.html with every specimen's R
// curve and fit overlaid (gnuplot), the per-specimen parameter table (value
// or lower bound, total 95% interval, outlier flags), the campaign's
// statistics and the joint fit. The input is a value (campaign::
// WriteCampaignOutputs builds it from the campaign's result); like the fit
// report it is staged in a temporary folder and renamed when complete.

#include <filesystem>
#include <string>
#include <vector>

#include "bridgefit/report/report.hpp"
#include "bridgefit/report/report_input.hpp"

namespace bridgefit::report {

struct CampaignSpecimenView {
  std::string name, status, error;
  std::vector<double> crack_length, R;                   // data [m], [J/m^2]
  std::vector<double> fitted_crack_length, fitted_R;     // the fit's model [m], [J/m^2]
  std::vector<Estimate> estimates;  // sigma_c [Pa], J_B, delta_c [m], J_tip_c (SI)
  std::vector<std::string> outlier_in;                   // parameters it is flagged in
};

// One row of the statistics table, already in display units.
struct CampaignStatisticView {
  std::string parameter, unit;
  int values = 0, bounds = 0;
  double mean = NAN, sd = NAN, cv_percent = NAN, median = NAN, lower_bound = NAN;
  std::string bound_from, outliers, note;
};

struct CampaignView {
  std::string name;
  std::vector<CampaignSpecimenView> specimens;
  std::vector<CampaignStatisticView> statistics;
  std::string joint_text;  // the joint fit's summary (preformatted), or empty
};

// Writes `out_dir`/index.html and rcurves.png. Throws Error(kRuntime) when
// gnuplot fails, Error(kUsage) for bad options.
ReportSummary WriteCampaignReport(const CampaignView& view, const std::filesystem::path& out_dir,
                                  const ReportOptions& options = {});

}  // namespace bridgefit::report
