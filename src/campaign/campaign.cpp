// Test campaigns: requests from a manifest, specimens in parallel, statistics.
#include "bridgefit/campaign/campaign.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/settings.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/inverse/compliance_calibration.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "outcome_wire.hpp"

namespace bridgefit::campaign {
namespace {

// The choice a specimen makes, or else the campaign's, with the manifest
// line it was written on (0 when neither wrote it).
struct Choice {
  std::string text;
  int line = 0;
};
Choice Pick(const std::string& own, const std::map<std::string, int>& own_lines,
            const std::string& shared, const std::map<std::string, int>& shared_lines,
            const char* key, const std::string& fallback) {
  auto line_of = [key](const std::map<std::string, int>& lines) {
    const auto it = lines.find(key);
    return it == lines.end() ? 0 : it->second;
  };
  if (!own.empty()) return {own, line_of(own_lines)};
  if (!shared.empty()) return {shared, line_of(shared_lines)};
  return {fallback, 0};
}

// Runs `parse`; an Error it throws is re-thrown naming the manifest line and key.
template <class F>
auto Parsed(F&& parse, const io::CampaignManifest& m, const io::ManifestSpecimen& sp,
            const char* key, const Choice& choice) {
  try {
    return parse(choice.text);
  } catch (const Error& e) {
    throw Error(ErrorKind::kInput, e.message(),
                {.file = m.path.string(), .line = choice.line ? choice.line : sp.line,
                 .field = fmt::format("{} (specimen '{}')", key, sp.name), .value = choice.text,
                 .expected = e.context().expected});
  }
}

pipeline::FitRequest RequestFor(const io::CampaignManifest& m, const io::ManifestSpecimen& sp) {
  pipeline::FitRequest r;
  r.input_path = sp.record.string();
  r.scene = sp.scene;
  r.scene_path = sp.scene_path.string();
  const auto pick = [&](const std::string& own, const std::string& shared, const char* key,
                        const std::string& fallback) {
    return Pick(own, sp.lines, shared, m.lines, key, fallback);
  };
  const io::ManifestChoices& a = sp.choices;
  const io::ManifestChoices& b = m.choices;
  r.columns = pick(a.columns, b.columns, "columns", "").text;
  r.units = pick(a.units, b.units, "units", "").text;
  const Choice method = pick(a.rcurve_method, b.rcurve_method, "rcurve_method", "energy");
  r.reduction.method = Parsed([](const std::string& t) { return experiment::ParseRMethod(t); }, m,
                              sp, "rcurve_method", method);
  r.reduction_given = method.line != 0;
  const Choice model{m.model, m.lines.count("model") ? m.lines.at("model") : 0};
  r.model = Parsed([](const std::string& t) { return pipeline::ParseModelChoice(t); }, m, sp,
                   "model", model);
  if (m.resolution) r.resolution = *m.resolution;
  const Choice law{m.law, m.lines.count("law") ? m.lines.at("law") : 0};
  Parsed([&r](const std::string& t) { return pipeline::SetFitLaw(t, r); }, m, sp, "law", law);
  r.target = Parsed([](const std::string& t) { return inverse::ParseFitTarget(t); }, m, sp,
                    "fit_to", pick(a.fit_to, b.fit_to, "fit_to", "r-curve"));
  r.calibration = Parsed(
      [](const std::string& t) { return inverse::ParseComplianceCalibrationMode(t); }, m, sp,
      "calibrate_compliance", pick(a.calibrate_compliance, b.calibrate_compliance,
                                   "calibrate_compliance", ""));
  r.fit.profile_likelihood = m.profile;
  std::string why;
  if (!r.IsValid(&why))
    throw Error(ErrorKind::kInput, why,
                {.file = m.path.string(), .line = sp.line,
                 .field = fmt::format("specimen '{}'", sp.name),
                 .expected = "choices a single `bridgefit fit` would accept"});
  return r;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A specimen's DIC: its crack lengths into the fit request, its /dic file
// as bytes, its per-frame warnings into the specimen's notes. A failure
// throws Error naming the images (the specimen's reason).
void RunDic(SpecimenOutcome& out) {
  dic::CrackSequenceOptions options = out.dic->options;
  options.correlation.threads = out.request.fit.threads;  // the specimen's share of the cores
  const std::string source = "DIC of " + out.dic->folder.string();
  dic::CrackSequenceResult result;
  try {
    result = dic::AnalyzeCrackSequence(out.dic->images, options);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::kInterrupted) throw;
    throw Error(e.kind(), "the DIC of the specimen's images failed: " + e.message(), e.context())
        .WithContext({.file = out.dic->folder.string()});
  }
  // The lengths as `rcurve --crack-length-from` reads them from the CSV:
  // the doubtful ones left out.
  pipeline::DicCrackLengths lengths;
  std::vector<std::string> flags;
  for (std::size_t k = 0; k < result.frames.size(); ++k) {
    const dic::FrameResult& f = result.frames[k];
    lengths.image.push_back(f.image);
    lengths.crack_length.push_back(f.has_length ? f.crack_length_m : NAN);
    flags.push_back(f.Flags());
    const std::string file = std::filesystem::path(f.image).filename().string();
    if (k > 0 && !f.has_length) out.notes.push_back(fmt::format("DIC {}: no crack length", file));
    else if (f.flagged) out.notes.push_back(fmt::format("DIC {}: flagged {}", file, f.Flags()));
  }
  pipeline::LeaveOutDoubtfulLengths(flags, lengths);
  out.notes.insert(out.notes.end(), lengths.notes.begin(), lengths.notes.end());
  pipeline::FitRequest::FrameCrackLengths frames;
  frames.source = source;
  frames.image = std::move(lengths.image);
  frames.crack_length = std::move(lengths.crack_length);
  out.request.frame_crack_lengths = std::move(frames);
  // The dic file's one writer, through a temporary file of this process
  // (numbered: two campaigns of one process may run side by side).
  static std::atomic<unsigned> serial{0};
  const std::filesystem::path temporary =
      std::filesystem::temp_directory_path() /
      fmt::format("bf_campaign_dic_{}_{}_{}.h5", static_cast<long>(::getpid()), serial++,
                  out.name);
  pipeline::WriteDicH5(temporary.string(), result, options);
  out.dic_file = ReadFileLimited(temporary, std::uint64_t{1} << 40, "",
                                 "this specimen's DIC file");
  std::error_code ec;
  std::filesystem::remove(temporary, ec);
}

// One specimen through its DIC (with images) and RunFit; an Error is the
// specimen's reason, not the campaign's.
void RunOne(SpecimenOutcome& out) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (out.dic) RunDic(out);
    out.run = pipeline::RunFit(out.request);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::kInterrupted) throw;
    out.error = e.what();
  } catch (const std::exception& e) {
    out.error = std::string("unexpected failure: ") + e.what();
  }
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string OutcomeLine(const SpecimenOutcome& s) {
  if (!s.ran()) return fmt::format("{}: failed ({:.1f} s): {}", s.name, s.wall_s, s.error);
  return fmt::format("{}: {} ({:.1f} s)", s.name,
                     s.run->summary.converged ? "fitted" : "fit did not converge", s.wall_s);
}

}  // namespace

bool CampaignOptions::IsValid(std::string* why) const {
  if (fit_threads < 0) {
    if (why) *why = fmt::format("fit_threads must be >= 0 (0: cores / jobs), got {}", fit_threads);
    return false;
  }
  if (jobs < 0) {
    if (why) *why = fmt::format("jobs must be >= 0 (0: the machine's cores), got {}", jobs);
    return false;
  }
  return true;
}

std::vector<pipeline::FitRequest> BuildRequests(const io::CampaignManifest& manifest) {
  std::vector<pipeline::FitRequest> requests;
  for (const io::ManifestSpecimen& sp : manifest.specimens) requests.push_back(RequestFor(manifest, sp));
  return requests;
}

inverse::SharedParameters JointSharedParameters(const io::CampaignManifest& manifest) {
  if (!manifest.joint) return inverse::kAllShared;
  try {
    return inverse::ParseSharedParameters(*manifest.joint);
  } catch (const Error& e) {
    const auto line = manifest.lines.find("joint");
    throw Error(ErrorKind::kInput, e.message(),
                {.file = manifest.path.string(),
                 .line = line == manifest.lines.end() ? 0 : line->second,
                 .field = "campaign.joint", .value = e.context().value,
                 .expected = e.context().expected});
  }
}

std::vector<std::optional<DicRequest>> BuildDicRequests(const io::CampaignManifest& manifest) {
  std::vector<std::optional<DicRequest>> requests;
  for (const io::ManifestSpecimen& sp : manifest.specimens) {
    if (!sp.dic) {
      requests.emplace_back();
      continue;
    }
    const io::ManifestDic& d = *sp.dic;
    // An error of the DIC settings, named by the key and line it came from.
    const auto fail = [&](const std::string& key, const std::string& message,
                          const std::string& value, const std::string& expected) {
      const std::string field = key.empty() ? "dic" : "dic." + key;  // "": the whole table
      const auto it = sp.lines.find(field);
      throw Error(ErrorKind::kInput, message,
                  {.file = manifest.path.string(),
                   .line = it != sp.lines.end() ? it->second : sp.lines.at("dic"),
                   .field = fmt::format("{} (specimen '{}')", field, sp.name), .value = value,
                   .expected = expected});
    };
    DicRequest r;
    r.folder = d.images;
    try {
      r.images = dic::ExpandImageArguments({d.images.string()});
    } catch (const Error& e) {
      fail("images", e.message(), d.images.string(),
           "a folder of the test's images (png, tif, bmp, jpg or pgm)");
    }
    if (r.images.size() < 2)
      fail("images", "need at least two images (a reference and a deformed one)",
           d.images.string(), "a folder of the test's images, the reference first");
    dic::DicSettings settings;
    settings.scale_m_per_px = d.scale_m_per_px;
    settings.offset_m = d.offset_m;
    if (d.crack_line)
      settings.crack_line = dic::CrackLine{(*d.crack_line)[0], (*d.crack_line)[1],
                                           (*d.crack_line)[2], (*d.crack_line)[3]};
    settings.fixed_line = d.fixed_line;
    settings.subset_px = d.subset_px;
    settings.step_px = d.step_px;
    settings.tip_method = d.tip_method;
    settings.threshold_px = d.threshold_px;
    settings.path_search_px = d.path_search_px;
    try {
      r.options = dic::MakeSequenceOptions(settings);
    } catch (const Error& e) {
      std::string key = e.context().field;  // "fixed_line", "crack_line" or "--tip-method"
      if (key.rfind("--", 0) == 0) key = key.substr(2);
      std::replace(key.begin(), key.end(), '-', '_');
      fail(key, e.message(), e.context().value, e.context().expected);
    }
    std::string why;
    if (!r.options.IsValid(&why))
      fail("", "the DIC settings are not valid: " + why, "",
           "settings `bridgefit dic` would accept (docs/DIC.md)");
    requests.push_back(std::move(r));
  }
  return requests;
}

ParameterStatistics Summarise(const std::string& parameter, const std::string& unit, double scale,
                              const std::vector<NamedEstimate>& estimates) {
  ParameterStatistics st;
  st.parameter = parameter;
  st.unit = unit;
  st.scale = scale;
  std::vector<double> values;
  std::vector<std::string> names;
  for (const NamedEstimate& e : estimates) {
    if (std::isfinite(e.estimate.value)) {
      values.push_back(e.estimate.value);
      names.push_back(e.specimen);
    } else if (std::isfinite(e.estimate.lower_bound)) {
      ++st.bounds;
      if (!(e.estimate.lower_bound <= st.campaign_lower_bound)) {
        st.campaign_lower_bound = e.estimate.lower_bound;
        st.bound_from = e.specimen;
      }
    }
  }
  st.values = static_cast<int>(values.size());
  if (!values.empty()) {
    double sum = 0;
    for (double v : values) sum += v;
    st.mean = sum / values.size();
    st.median = Median(values);
  }
  if (values.size() >= 2) {
    double ss = 0;
    for (double v : values) ss += (v - st.mean) * (v - st.mean);
    st.sd = std::sqrt(ss / (values.size() - 1));
    st.cv = st.mean != 0 ? st.sd / std::abs(st.mean) : NAN;
  }
  if (values.size() >= 3) {
    std::vector<double> deviations;
    for (double v : values) deviations.push_back(std::abs(v - st.median));
    const double mad = Median(deviations);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double off = std::abs(values[i] - st.median);
      const bool flagged = mad > 0 ? 0.6745 * off / mad > kOutlierModifiedZ
                                   : off > 1e-9 * std::abs(st.median);
      if (flagged) st.outliers.push_back(names[i]);
    }
  }
  if (st.values == 0 && st.bounds == 0) {
    st.note = "no specimen gives a value or a bound";
  } else if (st.bounds > 0 && st.values == 0) {
    st.note = fmt::format(
        "every specimen that gives it gives only a lower bound (no steady state); the largest, "
        "{:.4g} {} from {}, is the campaign's lower bound",
        st.campaign_lower_bound * scale, unit, st.bound_from);
  } else if (st.bounds > 0) {
    st.note = fmt::format(
        "{} specimen(s) give only a lower bound (largest {:.4g} {} from {}); mean and SD are "
        "over the {} that identify it",
        st.bounds, st.campaign_lower_bound * scale, unit, st.bound_from, st.values);
  }
  if (!st.outliers.empty()) {
    std::string list;
    for (const std::string& n : st.outliers) list += (list.empty() ? "" : ", ") + n;
    st.note += fmt::format("{}outlier(s) flagged, not dropped: {} (modified z-score > {})",
                           st.note.empty() ? "" : "; ", list, kOutlierModifiedZ);
  }
  return st;
}

int CampaignResult::Failed() const {
  int n = 0;
  for (const SpecimenOutcome& s : specimens) n += s.ok() ? 0 : 1;
  return n;
}

namespace {

// --joint: every converged specimen into one fit; an error is kept as the
// campaign's joint_error (the separate fits stand). Over several ranks every
// rank makes it (its parts dealt over them, pipeline::RunJointFit) and
// rank 0's result is the campaign's.
void RunJoint(CampaignResult& result, const CampaignOptions& options,
              const inverse::SharedParameters& shared, parallel::Communicator& comm) {
  std::vector<pipeline::FitRequest> requests;
  std::vector<const pipeline::FitRun*> runs;
  std::vector<std::string> names;
  std::string error;
  for (SpecimenOutcome& s : result.specimens) {
    if (!s.ok()) continue;
    // Run on another rank: its input was not sent; reading it again gives
    // the same input (the record and its reduction are deterministic).
    if (s.rank != comm.rank() && error.empty()) {
      try {
        s.run->input = pipeline::ResolveFitInput(s.request);
      } catch (const Error& e) {
        error = fmt::format("specimen '{}': {}", s.name, e.what());
      }
    }
    requests.push_back(s.request), runs.push_back(&*s.run), names.push_back(s.name);
  }
  // All ranks go on to the joint fit, or none.
  if (const std::string first = comm.FirstError(error); !first.empty()) {
    result.joint_error = first;
    return;
  }
  if (options.progress && comm.root())
    options.progress(fmt::format("joint fit of {} converged specimens{} ...", runs.size(),
                                 comm.size() > 1 ? fmt::format(" on {} ranks", comm.size()) : ""));
  try {
    result.joint = pipeline::RunJointFit(requests, runs, names, &comm, shared);
  } catch (const Error& e) {
    // Over ranks, an error that only this rank has (or an interrupt) ends
    // the job (the others wait for it); one every rank has stays the
    // campaign's joint_error, as on one process.
    const bool every_rank = e.kind() == ErrorKind::kInput || e.kind() == ErrorKind::kUsage ||
                            e.context().field == pipeline::kRanksAgreeField;
    if (comm.size() > 1 && !every_rank) throw;
    result.joint_error = e.what();
  }
}

// The specimens `mine` (indices into result.specimens) on result.jobs
// threads; an interrupt stops taking specimens and is re-thrown.
void RunSpecimens(CampaignResult& result, const std::vector<std::size_t>& mine,
                  const CampaignOptions& options) {
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  std::exception_ptr interrupted;
  auto report = [&](const std::string& line) {
    if (!options.progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    options.progress(line);
  };
  const std::size_t total = result.specimens.size();
  auto worker = [&]() {
    for (std::size_t k; (k = next++) < mine.size();) {
      const std::size_t i = mine[k];
      SpecimenOutcome& s = result.specimens[i];
      report(fmt::format("[{}/{}] {}: started", i + 1, total, s.name));
      try {
        RunOne(s);
      } catch (...) {  // an interrupt: stop taking specimens
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (!interrupted) interrupted = std::current_exception();
        next = mine.size();
        return;
      }
      report(fmt::format("[{} done of {}] {}", ++done, mine.size(), OutcomeLine(s)));
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < result.jobs; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  if (interrupted) std::rethrow_exception(interrupted);
}

// The cores a rank of an MPI job may use: those it is bound to (srun
// --cpus-per-task, mpirun --bind-to core), or else its node's cores shared by
// the node's ranks.
int RankCores(int ranks_on_node) {
  const int node = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int allowed = node;
#ifdef __linux__
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) allowed = CPU_COUNT(&set);
#endif
  if (allowed > 0 && allowed < node) return allowed;
  return std::max(1, node / std::max(1, ranks_on_node));
}

// Statistics per parameter over the specimens that ran and converged.
void ComputeStatistics(CampaignResult& result) {
  struct Parameter {
    const char* name;
    const char* unit;
    double scale;
    inverse::ParameterEstimate inverse::FitSummary::*member;
  };
  const Parameter parameters[] = {{"sigma_c", "MPa", 1e-6, &inverse::FitSummary::sigma_c},
                                  {"J_B", "J/m^2", 1.0, &inverse::FitSummary::J_B},
                                  {"delta_c", "mm", 1e3, &inverse::FitSummary::delta_c},
                                  {"J_tip_c", "J/m^2", 1.0, &inverse::FitSummary::J_tip_c}};
  for (const Parameter& p : parameters) {
    std::vector<NamedEstimate> estimates;
    for (const SpecimenOutcome& s : result.specimens)
      // Without bridging, only the tip toughness is a property of the test.
      if (s.ok() && (s.run->summary.bridging_detected || p.member == &inverse::FitSummary::J_tip_c))
        estimates.push_back({s.name, s.run->summary.*p.member});
    result.statistics.push_back(Summarise(p.name, p.unit, p.scale, estimates));
  }
}

}  // namespace

CampaignResult RunCampaign(const io::CampaignManifest& manifest, const CampaignOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, why, {.field = "--jobs"});
  const std::unique_ptr<parallel::Communicator> serial = parallel::MakeSerialCommunicator();
  parallel::Communicator& comm = options.communicator ? *options.communicator : *serial;
  std::vector<pipeline::FitRequest> requests = BuildRequests(manifest);  // before any work
  std::vector<std::optional<DicRequest>> dics = BuildDicRequests(manifest);
  const inverse::SharedParameters manifest_shared = JointSharedParameters(manifest);
  const inverse::SharedParameters shared =
      options.joint_parameters ? *options.joint_parameters : manifest_shared;
  CampaignResult result;
  result.manifest = manifest;
  result.ranks = comm.size();
  for (std::size_t i = 0; i < requests.size(); ++i) {
    SpecimenOutcome s;
    s.name = manifest.specimens[i].name;
    s.request = std::move(requests[i]);
    s.dic = std::move(dics[i]);
    result.specimens.push_back(std::move(s));
  }
  // Round-robin in manifest order: who runs a specimen depends only on N.
  std::vector<std::size_t> mine;
  for (std::size_t i = comm.rank(); i < result.specimens.size(); i += comm.size()) mine.push_back(i);
  const int hw = comm.mpi() ? RankCores(comm.local_size())
                                 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  result.jobs = std::clamp(options.jobs > 0 ? options.jobs : hw, 1,
                           std::max(1, static_cast<int>(mine.size())));
  // The cores are shared: each fit's profiles get hw / jobs threads (the
  // default 2 per fit over-subscribed 2 cores with 2 specimens at once:
  // speed-up 0.98, bench/campaign_bench.cpp); a thread count the request
  // sets wins. Threads do not change a fit's result (inverse/fit.hpp).
  for (SpecimenOutcome& s : result.specimens) {
    s.rank = static_cast<int>((&s - result.specimens.data()) % comm.size());
    if (s.request.fit.threads == 0)
      s.request.fit.threads =
          options.fit_threads > 0 ? options.fit_threads : std::max(1, hw / result.jobs);
  }
  const auto t0 = std::chrono::steady_clock::now();
  RunSpecimens(result, mine, options);
  if (comm.size() > 1) {
    wire::GatherOutcomes(result, mine, comm);
    result.complete = comm.root();
  }
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (result.complete) ComputeStatistics(result);
  if (options.joint) {
    // Every rank joins the joint fit with every specimen's outcome.
    if (comm.size() > 1) wire::ShareOutcomes(result, mine, comm);
    RunJoint(result, options, shared, comm);
  }
  return result;
}

}  // namespace bridgefit::campaign
