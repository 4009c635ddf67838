// Issue 17's validation campaign (docs/VALIDATION.md): N synthetic tests
// drawn at random, generated at 4x finer elements than the fit may use,
// fitted with the product's defaults, checked against the truth.
//   bf_validate [cases=300] [seed=17] [jobs=2] [out_dir=out/validate] [first=0] [max_wall_s=0]
// (max_wall_s > 0: no case starts after it; the summary covers the cases run)
// writes OUT/validation.csv (one row per case, flushed as cases finish),
// OUT/validation_summary.txt (table and every failure), and
// OUT/validation.gp / OUT/validation.png (gnuplot, when found). Exit status:
// 0 with no silent failure, 1 with some, 2 for a usage error.
//   bf_validate 22,37,40 [seed] [jobs] [out_dir]   runs the listed cases only
//   bf_validate --scene SEED INDEX   prints case INDEX as a scene TOML with
//                                    the synth and fit commands that rerun it
// BF_VALIDATE_IMAGES=N: the first N CT energy cases of those run also run on
// the images route (images -> DIC -> fit), as extra rows labelled "images";
// the draws themselves are unchanged.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "validation.hpp"

using namespace bridgefit::validate;

int main(int argc, char** argv) {
  if (argc > 1 && (std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help")) {
    std::printf(
        "usage: bf_validate [cases=300 | i,j,k] [seed=17] [jobs=2] [out_dir=out/validate] "
        "[first=0] [max_wall_s=0]\n       bf_validate --scene SEED INDEX\n"
        "BF_VALIDATE_IMAGES=N: the first N CT energy cases also run as images -> DIC -> fit\n"
        "BF_VALIDATE_FAR_FIELD=F: the generator's far-field element, a multiple of the model's "
        "default (0.5: finer than the fit's everywhere; 1: the fit's own)\n");
    return 0;
  }
  // The generator finer than the fit everywhere by default (its far field
  // too: docs/VALIDATION.md run E); BF_VALIDATE_FAR_FIELD=1 shares the fit's.
  DrawOptions draw;
  draw.far_field = 0.5;
  if (const char* far = std::getenv("BF_VALIDATE_FAR_FIELD")) draw.far_field = std::atof(far);
  if (argc == 4 && std::string(argv[1]) == "--scene") {  // bf_validate --scene SEED INDEX
    std::fputs(
        ReproductionToml(DrawCase(std::strtoull(argv[2], nullptr, 10), std::atoi(argv[3]), draw))
            .c_str(),
        stdout);
    return 0;
  }
  // The first argument is a count, or a list of case indices ("22,37,40").
  std::vector<int> indices;
  const std::string first_arg = argc > 1 ? argv[1] : "300";
  const bool listed = first_arg.find(',') != std::string::npos;
  if (listed) {
    std::stringstream stream(first_arg);
    for (std::string item; std::getline(stream, item, ',');) indices.push_back(std::atoi(item.c_str()));
  }
  const int cases = listed ? static_cast<int>(indices.size()) : std::atoi(first_arg.c_str());
  const unsigned long long seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 17;
  const int jobs = argc > 3 ? std::max(1, std::atoi(argv[3])) : 2;
  const std::filesystem::path out = argc > 4 ? argv[4] : "out/validate";
  const int first = argc > 5 ? std::atoi(argv[5]) : 0;
  const double max_wall_s = argc > 6 ? std::atof(argv[6]) : 0.0;
  if (!listed)
    for (int i = 0; i < cases; ++i) indices.push_back(first + i);
  if (cases <= 0) {
    std::fprintf(stderr, "bf_validate: cases must be positive\n");
    return 2;
  }
  std::vector<ValidationCase> specs;
  for (int index : indices) specs.push_back(DrawCase(seed, index, draw));
  const char* images_env = std::getenv("BF_VALIDATE_IMAGES");
  int images_left = images_env ? std::atoi(images_env) : 0;
  for (int i = 0; i < cases && images_left > 0; ++i) {
    if (specs[i].route != Route::kEnergy ||
        specs[i].scene.specimen.type != bridgefit::SpecimenType::kCT)
      continue;
    ValidationCase by_images = specs[i];
    by_images.route = Route::kImages;
    specs.push_back(by_images);
    --images_left;
  }
  const int rows = static_cast<int>(specs.size());
  std::filesystem::create_directories(out);
  const std::string base = "validation";
  const auto t0 = std::chrono::steady_clock::now();

  auto elapsed = [&t0] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::vector<CaseResult> results(rows);
  std::vector<char> finished(rows, 0);
  std::atomic<int> next{0};
  std::mutex io;
  std::ofstream csv(out / (base + ".csv"));
  csv << CaseCsvHeader() << std::flush;
  int done = 0;
  // Cases side by side, each fit serial inside (threads = 1) when jobs > 1.
  auto worker = [&] {
    for (int i = next++; i < rows; i = next++) {
      if (max_wall_s > 0.0 && elapsed() > max_wall_s) break;
      const ValidationCase& spec = specs[i];
      results[i] = RunCase(spec, jobs > 1 ? 1 : 0);
      std::lock_guard<std::mutex> lock(io);
      finished[i] = 1;
      csv << CaseCsvRow(results[i]) << std::flush;
      const CaseResult& r = results[i];
      std::printf("[%d/%d] %s: %s, fit %.1f s%s\n", ++done, rows, spec.Label().c_str(),
                  r.ran ? "ok" : r.error.c_str(), r.fit_s,
                  r.ran && (r.parameters[0].silent_failure || r.parameters[1].silent_failure ||
                            r.parameters[2].silent_failure)
                      ? "  SILENT FAILURE"
                      : "");
      std::fflush(stdout);
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  const double wall = elapsed();
  std::vector<CaseResult> run;
  for (int i = 0; i < rows; ++i)
    if (finished[i]) run.push_back(std::move(results[i]));

  const CampaignStats stats = Summarise(run);
  std::string text = "bf_validate " + std::to_string(run.size()) + " of " +
                     std::to_string(rows) + " rows run (" + std::to_string(rows - cases) +
                     " of them the images route's), seed " +
                     std::to_string(seed) + ", first case " + std::to_string(first) + ", " +
                     std::to_string(jobs) + " jobs, wall " + std::to_string(int(wall)) + " s\n";
  text += SummaryTable(stats);
  text += "\nevery failure (|error| > 2 half-widths or a bound above the truth):\n";
  text += FailureList(run, false);
  text += "\nbridging not detected although the true R rose >= 10% of J_tip,c:\n";
  text += MissedBridgingList(run);
  std::ofstream(out / (base + "_summary.txt")) << text;
  std::ofstream(out / (base + "_coverage.dat")) << CoverageData(stats);
  std::ofstream(out / (base + ".gp")) << GnuplotScript(base);
  std::fputs(text.c_str(), stdout);
  const std::string plot = "cd '" + out.string() + "' && gnuplot " + base + ".gp 2>/dev/null";
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0 && std::system(plot.c_str()) == 0)
    std::printf("chart: %s\n", (out / (base + ".png")).c_str());
  return stats.silent_failures == 0 ? 0 : 1;
}
