// The campaign's text report and files (summary.csv, statistics.csv, one fit
// file per specimen, written by the fit file's owner, and campaign.h5: each
// specimen's fit file under /specimens/<name> plus /campaign).
#include <cmath>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "bridgefit/campaign/campaign.hpp"
#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/report/campaign_report.hpp"

namespace bridgefit::campaign {
namespace {

std::string Number(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : ""; }

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string Field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

const inverse::ParameterEstimate& Estimate(const inverse::FitSummary& s, const std::string& name) {
  if (name == "sigma_c") return s.sigma_c;
  if (name == "J_B") return s.J_B;
  if (name == "delta_c") return s.delta_c;
  return s.J_tip_c;
}

std::string Status(const SpecimenOutcome& s) {
  if (!s.ran()) return "failed";
  if (!s.run->summary.converged) return "not converged";
  return s.run->summary.bridging_detected ? "fitted" : "no bridging";
}

// "0.45 [0.43, 0.47]", ">= 500" or "-".
std::string Cell(const inverse::ParameterEstimate& e, double scale) {
  if (std::isfinite(e.value)) {
    std::string text = fmt::format("{:.4g}", e.value * scale);
    if (std::isfinite(e.ci95_low) && std::isfinite(e.ci95_high))
      text += fmt::format(" [{:.4g}, {:.4g}]", e.ci95_low * scale, e.ci95_high * scale);
    return text;
  }
  if (std::isfinite(e.lower_bound)) return fmt::format(">= {:.4g}", e.lower_bound * scale);
  return "-";
}

// specimens/dic/<name>.h5: a specimen's DIC file (pipeline::WriteDicH5's).
std::filesystem::path DicFilePath(const std::filesystem::path& dir, const SpecimenOutcome& s) {
  return dir / "specimens" / "dic" / (s.name + ".h5");
}

std::string SummaryCsv(const CampaignResult& r) {
  std::ostringstream out;
  out << "specimen,status,record,wall [s]";
  for (const ParameterStatistics& p : r.statistics) {
    const std::string u = p.unit;
    out << fmt::format(",{0} [{1}],{0} kind,{0} ci95 low [{1}],{0} ci95 high [{1}],{0} interval",
                       p.parameter, u);
  }
  out << ",outlier in,error,notes\n";
  for (const SpecimenOutcome& s : r.specimens) {
    out << Field(s.name) << "," << Status(s) << "," << Field(s.request.input_path) << ","
        << fmt::format("{:.2f}", s.wall_s);
    std::string outlier_in;
    for (const ParameterStatistics& p : r.statistics) {
      for (const std::string& n : p.outliers)
        if (n == s.name) outlier_in += (outlier_in.empty() ? "" : " ") + p.parameter;
      if (!s.ok()) {
        out << ",,,,,";
        continue;
      }
      const inverse::ParameterEstimate& e = Estimate(s.run->summary, p.parameter);
      const bool value = std::isfinite(e.value);
      const bool bound = !value && std::isfinite(e.lower_bound);
      out << "," << Number((value ? e.value : e.lower_bound) * p.scale) << ","
          << (value ? "value" : bound ? "lower bound" : "none") << ","
          << Number(e.ci95_low * p.scale) << "," << Number(e.ci95_high * p.scale) << ","
          << (value ? inverse::IntervalStatusName(e.interval_status) : "");
    }
    std::string notes;
    for (const std::string& n : s.notes) notes += (notes.empty() ? "" : "; ") + n;
    out << "," << outlier_in << "," << Field(s.error) << "," << Field(notes) << "\n";
  }
  return out.str();
}

std::string StatisticsCsv(const CampaignResult& r) {
  std::ostringstream out;
  out << "parameter,unit,values,bounds,mean,sd,cv [%],median,campaign lower bound,bound from,"
         "outliers,note\n";
  for (const ParameterStatistics& p : r.statistics) {
    std::string outliers;
    for (const std::string& n : p.outliers) outliers += (outliers.empty() ? "" : " ") + n;
    out << p.parameter << "," << p.unit << "," << p.values << "," << p.bounds << ","
        << Number(p.mean * p.scale) << "," << Number(p.sd * p.scale) << ","
        << Number(p.cv * 100) << "," << Number(p.median * p.scale) << ","
        << Number(p.campaign_lower_bound * p.scale) << "," << Field(p.bound_from) << ","
        << Field(outliers) << "," << Field(p.note) << "\n";
  }
  return out.str();
}

}  // namespace

namespace {

// One row per parameter of the joint fit (value or lower bound, total 95%
// interval) with the consistency test's figures repeated on each row.
std::string JointCsv(const pipeline::JointFitRun& joint) {
  std::ostringstream out;
  out << "parameter,unit,value,ci95_low,ci95_high,lower_bound,specimens,likelihood_ratio,"
         "degrees_of_freedom,p_value,consistent,shared,carried_by\n";
  const inverse::FitSummary& f = joint.summary;
  const std::tuple<const char*, const char*, double, const inverse::ParameterEstimate*> rows[] = {
      {"sigma_c", "MPa", 1e-6, &f.sigma_c}, {"J_B", "J/m^2", 1.0, &f.J_B},
      {"delta_c", "mm", 1e3, &f.delta_c}, {"J_tip_c", "J/m^2", 1.0, &f.J_tip_c}};
  auto number = [](double v, double scale) {
    return std::isfinite(v) ? fmt::format("{:.6g}", v * scale) : std::string();
  };
  const inverse::ConsistencyTest& t = joint.consistency;
  for (const auto& [name, unit, scale, e] : rows) {
    // delta_c is shared when J_B and sigma_c are; carriers are the shared
    // parameters' (";"-separated specimens).
    const std::string n = name;
    const bool shared = n == "delta_c" ? joint.shared[inverse::kJB] && joint.shared[inverse::kSigmaC]
                                       : joint.shared[n == "sigma_c" ? inverse::kSigmaC
                                                      : n == "J_B"   ? inverse::kJB
                                                                     : inverse::kJTipC];
    std::string carriers;
    for (const pipeline::ParameterCarriers& c : joint.carriers)
      if (n == inverse::ParameterName(c.parameter))
        for (const std::string& sp : c.specimens) carriers += (carriers.empty() ? "" : ";") + sp;
    out << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", name, unit,
                       number(e->value, scale), number(e->ci95_low, scale),
                       number(e->ci95_high, scale), number(e->lower_bound, scale),
                       joint.specimens.size(), number(t.statistic, 1.0), t.degrees_of_freedom,
                       number(t.p_value, 1.0), t.consistent() ? 1 : 0, shared ? 1 : 0, carriers);
  }
  return out.str();
}

// Each specimen's own values of the parameters the joint fit does not share.
std::string JointOwnCsv(const pipeline::JointFitRun& joint) {
  std::ostringstream out;
  out << "specimen,parameter,unit,value,ci95_low,ci95_high,conditional_ci95_low,"
         "conditional_ci95_high\n";
  auto number = [](double v, double scale) {
    return std::isfinite(v) ? fmt::format("{:.6g}", v * scale) : std::string();
  };
  for (const pipeline::OwnParameterValue& v : joint.own_values) {
    const bool stress = v.parameter == inverse::kSigmaC;
    const double scale = stress ? 1e-6 : 1.0;
    out << fmt::format("{},{},{},{},{},{},{},{}\n", v.specimen, inverse::ParameterName(v.parameter),
                       stress ? "MPa" : "J/m^2", number(v.value, scale), number(v.ci95_low, scale),
                       number(v.ci95_high, scale), number(v.conditional_ci95_low, scale),
                       number(v.conditional_ci95_high, scale));
  }
  return out.str();
}

}  // namespace

std::string CampaignResult::BriefReport() const {
  std::ostringstream out;
  const std::string where = ranks > 1 ? fmt::format("{} MPI ranks x {} thread(s)", ranks, jobs)
                                      : fmt::format("{} thread(s)", jobs);
  out << fmt::format("campaign '{}': {} specimens, {} ran on {} in {:.1f} s, {} failed\n",
                     manifest.name, specimens.size(), specimens.size() - Failed(), where, wall_s,
                     Failed());
  out << fmt::format("  {:<16} {:<14}", "specimen", "status");
  for (const ParameterStatistics& p : statistics)
    out << fmt::format(" {:<26}", p.parameter + " [" + p.unit + "]");
  out << "\n";
  for (const SpecimenOutcome& s : specimens) {
    out << fmt::format("  {:<16} {:<14}", s.name, Status(s));
    for (const ParameterStatistics& p : statistics)
      out << fmt::format(" {:<26}", s.ok() ? Cell(Estimate(s.run->summary, p.parameter), p.scale) : "-");
    out << "\n";
    if (!s.ran()) out << "      " << s.error << "\n";
  }
  out << "  statistics (values of the specimens that identify each parameter):\n";
  for (const ParameterStatistics& p : statistics) {
    out << fmt::format("    {:<8} n = {}", p.parameter, p.values);
    if (p.values > 0) out << fmt::format(", mean {:.4g} {}", p.mean * p.scale, p.unit);
    if (p.values > 1)
      out << fmt::format(", SD {:.3g} {}, CV {:.1f}%", p.sd * p.scale, p.unit, p.cv * 100);
    if (p.bounds > 0)
      out << fmt::format(", campaign lower bound >= {:.4g} {} ({} bound(s))",
                         p.campaign_lower_bound * p.scale, p.unit, p.bounds);
    out << "\n";
    if (!p.note.empty()) out << "             " << p.note << "\n";
  }
  if (joint) out << joint->BriefReport();
  if (!joint_error.empty()) out << "  joint fit not run: " << joint_error << "\n";
  return out.str();
}

namespace {

// SI unit of a parameter's values in campaign.h5.
const char* SiUnit(const std::string& parameter) {
  return parameter == "sigma_c" ? "Pa" : parameter == "delta_c" ? "m" : "J/m^2";
}

// The joint fit's shared parameters, each specimen's own values of the
// others (/campaign/joint/own/NAME/*, over /campaign/joint/specimens) and the
// carriers of the shared ones (/campaign/joint/carriers/NAME/*).
void WriteJointSubset(io::H5Writer& file, const std::string& g, const pipeline::JointFitRun& j) {
  file.WriteAttribute(g, "shared_parameters", inverse::SharedParametersText(j.shared));
  for (int i = 0; i < inverse::kParameterCount; ++i) {
    const std::string name = inverse::ParameterName(i);
    file.WriteAttribute(g + "/parameters/" + name, "shared", j.shared[i] ? 1.0 : 0.0);
    if (j.shared[i]) continue;
    std::vector<double> value, low, high, cond_low, cond_high;
    for (const std::string& sp : j.specimens)
      for (const pipeline::OwnParameterValue& v : j.own_values)
        if (v.specimen == sp && v.parameter == i) {
          value.push_back(v.value), low.push_back(v.ci95_low), high.push_back(v.ci95_high);
          cond_low.push_back(v.conditional_ci95_low), cond_high.push_back(v.conditional_ci95_high);
        }
    if (value.size() != j.specimens.size()) continue;  // fixed by the user: none
    const std::string og = g + "/own/" + name;
    const std::string unit = SiUnit(name);
    file.WriteVector(og + "/value", value, unit, "per joint specimen, at the joint optimum");
    file.WriteVector(og + "/ci95_low", low, unit, "95%, the shared parameters' uncertainty included");
    file.WriteVector(og + "/ci95_high", high, unit, "95%, the shared parameters' uncertainty included");
    file.WriteVector(og + "/conditional_ci95_low", cond_low, unit, "95%, shared held at the joint values");
    file.WriteVector(og + "/conditional_ci95_high", cond_high, unit, "95%, shared held at the joint values");
  }
  file.WriteAttribute(g, "carrier_rule", std::string(pipeline::kCarrierRule));
  for (const pipeline::ParameterCarriers& c : j.carriers) {
    const std::string cg = g + "/carriers/" + inverse::ParameterName(c.parameter);
    file.WriteStrings(cg + "/specimens", c.specimens);
    file.WriteStrings(cg + "/reasons", c.reasons);
  }
}

// campaign.h5: every specimen's fit file (its own layout, copied from
// specimens/<name>.h5, which the fit file's owner wrote) under
// /specimens/<name>; /campaign: the specimens and their status, the
// statistics per parameter (SI, units on each) and the joint fit.
void WriteCampaignH5(const CampaignResult& result, const std::filesystem::path& dir) {
  io::H5Writer file(dir / "campaign.h5");
  std::vector<std::string> names, status;
  for (const SpecimenOutcome& s : result.specimens) {
    names.push_back(s.name);
    status.push_back(Status(s));
    if (s.ran()) file.CopyFileInto(dir / "specimens" / (s.name + ".h5"), "/specimens/" + s.name);
    if (!s.dic_file.empty())  // its /dic beside /fit, /rcurve and /experiment
      file.CopyFileInto(DicFilePath(dir, s), "/specimens/" + s.name);
  }
  const std::string c = "/campaign";
  file.WriteAttribute(c, "name", result.manifest.name);
  file.WriteAttribute(c, "specimens", static_cast<double>(result.specimens.size()));
  file.WriteAttribute(c, "failed", static_cast<double>(result.Failed()));
  file.WriteAttribute(c, "jobs", static_cast<double>(result.jobs));
  file.WriteAttribute(c, "ranks", static_cast<double>(result.ranks));
  file.WriteAttribute(c, "wall_s", result.wall_s);
  file.WriteStrings(c + "/specimen_names", names);
  file.WriteStrings(c + "/specimen_status", status);
  for (const ParameterStatistics& p : result.statistics) {
    const std::string g = c + "/statistics/" + p.parameter;
    const char* unit = SiUnit(p.parameter);
    file.WriteAttribute(g, "units", unit);
    file.WriteAttribute(g, "values", static_cast<double>(p.values));
    file.WriteAttribute(g, "bounds", static_cast<double>(p.bounds));
    file.WriteAttribute(g, "mean", p.mean);
    file.WriteAttribute(g, "sd", p.sd);
    file.WriteAttribute(g, "cv", p.cv);
    file.WriteAttribute(g, "median", p.median);
    file.WriteAttribute(g, "campaign_lower_bound", p.campaign_lower_bound);
    file.WriteAttribute(g, "bound_from", p.bound_from);
    std::string outliers;
    for (const std::string& n : p.outliers) outliers += (outliers.empty() ? "" : " ") + n;
    file.WriteAttribute(g, "outliers", outliers);
    file.WriteAttribute(g, "note", p.note);
    // Per specimen (manifest order; NaN where it gives none): value or
    // lower bound and the total 95% interval.
    std::vector<double> value, bound, low, high;
    for (const SpecimenOutcome& s : result.specimens) {
      const inverse::ParameterEstimate* e = s.ok() ? &Estimate(s.run->summary, p.parameter) : nullptr;
      value.push_back(e ? e->value : NAN);
      bound.push_back(e ? e->lower_bound : NAN);
      low.push_back(e ? e->ci95_low : NAN);
      high.push_back(e ? e->ci95_high : NAN);
    }
    file.WriteVector(g + "/value", value, unit, "per specimen (NaN: bound only or none)");
    file.WriteVector(g + "/lower_bound", bound, unit, "per specimen (PHYSICS 7)");
    file.WriteVector(g + "/ci95_low", low, unit, "total 95% interval, per specimen");
    file.WriteVector(g + "/ci95_high", high, unit, "total 95% interval, per specimen");
  }
  if (result.joint) {
    const pipeline::JointFitRun& j = *result.joint;
    const std::string g = c + "/joint";
    file.WriteStrings(g + "/specimens", j.specimens);
    file.WriteStrings(g + "/flagged", j.flagged);
    file.WriteAttribute(g, "likelihood_ratio", j.consistency.statistic);
    file.WriteAttribute(g, "degrees_of_freedom", static_cast<double>(j.consistency.degrees_of_freedom));
    file.WriteAttribute(g, "p_value", j.consistency.p_value);
    file.WriteAttribute(g, "consistent", j.consistency.consistent() ? 1.0 : 0.0);
    file.WriteAttribute(g, "model_error", j.model_error.Summary());
    file.WriteAttribute(g, "model_error_status", inverse::ModelErrorStatusName(j.model_error.status));
    const inverse::FitSummary& f = j.summary;
    const std::pair<const char*, const inverse::ParameterEstimate*> rows[] = {
        {"sigma_c", &f.sigma_c}, {"J_B", &f.J_B}, {"delta_c", &f.delta_c}, {"J_tip_c", &f.J_tip_c}};
    for (const auto& [name, e] : rows) {
      const std::string pg = g + "/parameters/" + name;
      file.WriteAttribute(pg, "units", SiUnit(name));
      file.WriteAttribute(pg, "value", e->value);
      file.WriteAttribute(pg, "ci95_low", e->ci95_low);
      file.WriteAttribute(pg, "ci95_high", e->ci95_high);
      file.WriteAttribute(pg, "statistical_ci95_low", e->statistical_ci95_low);
      file.WriteAttribute(pg, "statistical_ci95_high", e->statistical_ci95_high);
      file.WriteAttribute(pg, "model_bias", e->model_bias);
      file.WriteAttribute(pg, "lower_bound", e->lower_bound);
      file.WriteAttribute(pg, "identified", e->identified ? 1.0 : 0.0);
    }
    WriteJointSubset(file, g, j);
  }
  file.Commit();
}

// The report's view of an estimate (SI, as the fit file stores it).
report::Estimate EstimateView(const std::string& name, const inverse::ParameterEstimate& e) {
  report::Estimate v;
  v.name = name;
  v.units = SiUnit(name);
  v.value = e.value;
  v.ci_low = e.ci95_low;
  v.ci_high = e.ci95_high;
  v.lower_bound = e.lower_bound;
  v.present = true;
  v.identified = e.identified;
  v.fixed = e.fixed;
  v.note = e.note;
  return v;
}

// The campaign report's view of the result (report/campaign_report.hpp).
report::CampaignView CampaignReportView(const CampaignResult& result) {
  report::CampaignView view;
  view.name = result.manifest.name;
  for (const SpecimenOutcome& s : result.specimens) {
    report::CampaignSpecimenView v;
    v.name = s.name;
    v.status = Status(s);
    v.error = s.error;
    if (s.ran()) {
      const pipeline::FitRun& run = *s.run;
      v.crack_length = run.data.crack_length;
      v.R = run.data.R;
      v.fitted_crack_length = run.summary.fitted_crack_length;
      v.fitted_R = run.summary.fitted_R;
      if (s.ok())
        for (const char* name : {"sigma_c", "J_B", "delta_c", "J_tip_c"})
          v.estimates.push_back(EstimateView(name, Estimate(run.summary, name)));
    }
    for (const ParameterStatistics& p : result.statistics)
      for (const std::string& n : p.outliers)
        if (n == s.name) v.outlier_in.push_back(p.parameter);
    view.specimens.push_back(std::move(v));
  }
  for (const ParameterStatistics& p : result.statistics) {
    std::string outliers;
    for (const std::string& n : p.outliers) outliers += (outliers.empty() ? "" : " ") + n;
    view.statistics.push_back({p.parameter, p.unit, p.values, p.bounds, p.mean * p.scale,
                               p.sd * p.scale, p.cv * 100, p.median * p.scale,
                               p.campaign_lower_bound * p.scale, p.bound_from, outliers, p.note});
  }
  if (result.joint) view.joint_text = result.joint->BriefReport();
  return view;
}

}  // namespace

void WriteCampaignOutputs(const CampaignResult& result, const std::filesystem::path& dir) {
  if (!result.complete)
    throw Error(ErrorKind::kInternal,
                "a campaign result of a rank other than 0 holds only its own specimens: only rank "
                "0 writes the outputs",
                {.file = dir.string()});
  std::error_code ec;
  std::filesystem::create_directories(dir / "specimens", ec);
  if (ec)
    throw Error(ErrorKind::kRuntime, "cannot create the campaign's output folder",
                {.file = (dir / "specimens").string(), .value = ec.message()});
  for (const SpecimenOutcome& s : result.specimens) {
    if (!s.dic_file.empty()) {  // written by the dic file's writer, kept as bytes
      std::filesystem::create_directories(dir / "specimens" / "dic", ec);
      if (ec)
        throw Error(ErrorKind::kRuntime, "cannot create the campaign's DIC folder",
                    {.file = (dir / "specimens" / "dic").string(), .value = ec.message()});
      WriteTextFileAtomic(DicFilePath(dir, s), s.dic_file);
    }
    if (!s.ran()) continue;
    const std::filesystem::path path = dir / "specimens" / (s.name + ".h5");
    if (s.fit_file.empty())
      pipeline::WriteFitFile(path.string(), s.request, *s.run);
    else  // written by the rank that ran it (the same writer), sent as bytes
      WriteTextFileAtomic(path, s.fit_file);
  }
  WriteTextFileAtomic(dir / "statistics.csv", StatisticsCsv(result));
  if (result.joint) WriteTextFileAtomic(dir / "joint.csv", JointCsv(*result.joint));
  if (result.joint && !result.joint->own_values.empty())
    WriteTextFileAtomic(dir / "joint_own.csv", JointOwnCsv(*result.joint));
  WriteTextFileAtomic(dir / "summary.csv", SummaryCsv(result));
  WriteCampaignH5(result, dir);
  report::WriteCampaignReport(CampaignReportView(result), dir / "report");
}

namespace {

// The specimen whose fit stands for the campaign when there is no joint fit.
std::string DesignSpecimen(const io::H5Reader& r, std::string* why) {
  const std::string from = r.HasAttribute("/campaign/statistics/J_B", "bound_from")
                               ? r.ReadStringAttribute("/campaign/statistics/J_B", "bound_from")
                               : std::string();
  if (!from.empty() && r.Exists("/specimens/" + from + "/fit")) {
    *why = "it gives the campaign's lower bound of J_B";
    return from;
  }
  if (r.Exists("/campaign/specimen_names"))
    for (const std::string& name : r.ReadStrings("/campaign/specimen_names"))
      if (r.Exists("/specimens/" + name + "/fit")) {
        *why = "the first specimen with a fit";
        return name;
      }
  return "";
}

}  // namespace

pipeline::FittedLaw ReadCampaignLaw(const io::H5Reader& r, const std::filesystem::path& file) {
  const std::string j = "/campaign/joint";
  std::vector<std::string> joint;
  if (r.Exists(j + "/specimens")) joint = r.ReadStrings(j + "/specimens");
  if (!joint.empty() && r.Exists("/specimens/" + joint[0] + "/fit")) {
    pipeline::FittedLaw law = pipeline::ReadFittedLaw(r, file, "/specimens/" + joint[0]);
    // The joint fit's estimates replace the specimen's (SI, as written).
    const auto read = [&](const char* name, inverse::ParameterEstimate& e) {
      const std::string pg = j + "/parameters/" + name;
      if (!r.Exists(pg)) return;
      e = inverse::ParameterEstimate();
      e.value = r.ReadNumberAttribute(pg, "value");
      e.ci95_low = r.ReadNumberAttribute(pg, "ci95_low");
      e.ci95_high = r.ReadNumberAttribute(pg, "ci95_high");
      e.lower_bound = r.ReadNumberAttribute(pg, "lower_bound");
      e.identified = r.ReadNumberAttribute(pg, "identified") == 1.0;
      e.decided_by = "joint fit";
      // Not shared: the first joint specimen's own value at the joint optimum.
      const std::string own = j + "/own/" + name;
      if (!std::isfinite(e.value) && r.Exists(own + "/value")) {
        e.value = r.ReadVector(own + "/value").at(0);
        e.ci95_low = r.ReadVector(own + "/ci95_low").at(0);
        e.ci95_high = r.ReadVector(own + "/ci95_high").at(0);
        e.identified = std::isfinite(e.value);
        e.decided_by = "joint fit, " + joint[0] + "'s own value (not shared)";
      }
    };
    read("sigma_c", law.sigma_c);
    read("J_B", law.J_B);
    read("delta_c", law.delta_c);
    read("J_tip_c", law.J_tip_c);
    std::string names;
    for (const std::string& n : joint) names += (names.empty() ? "" : ", ") + n;
    law.group = j;
    law.note = fmt::format("the joint fit of {} specimen(s) ({}); {} (specimen {})", joint.size(),
                           names, law.note, joint[0]);
    return law;
  }
  std::string why;
  const std::string name = DesignSpecimen(r, &why);
  if (name.empty())
    throw Error(ErrorKind::kInput, "the campaign file holds no fitted specimen",
                {.file = file.string(), .field = "/specimens/NAME/fit",
                 .expected = "a campaign.h5 with at least one fitted specimen"});
  pipeline::FittedLaw law = pipeline::ReadFittedLaw(r, file, "/specimens/" + name);
  law.note = fmt::format("no joint fit in the campaign: specimen {}'s fit ({}); {}", name, why,
                         law.note);
  return law;
}

}  // namespace bridgefit::campaign
