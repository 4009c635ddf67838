// A campaign of 8 synthetic CT specimens (issue 19's bench): wall time on 1
// and 2 threads (speed-up), and the joint fit's time against the sum of the
// single fits. Specimens: the MDF sample's material and a linear law
// (sigma_c 1 MPa, J_B 500 J/m^2, J_tip,c 2210 J/m^2), four at W = 50 mm
// (never steady state) and four at W = 100 mm, made by `bridgefit synth`'s
// workflow at 0.25 mm elements (seeds 1-8, 0.5% load noise, 0.3 mm crack
// noise), fitted with the product's defaults (`--resolution auto`).
//   bf_campaign_bench OUT_PREFIX      -> OUT_PREFIX.csv
//   bf_campaign_bench --manifest DIR  -> DIR/campaign.toml and its records (MPI bench)
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/campaign/campaign.hpp"
#include "bridgefit/io/campaign_manifest.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/synth.hpp"

using namespace bridgefit;
namespace fs = std::filesystem;

namespace {

// The scene TOML of a CT of width W [mm] (the MDF sample's proportions).
std::string SceneToml(double width_mm) {
  return fmt::format(R"([specimen]
type = "ct"
width = "{0} mm"
height = "{1} mm"
thickness = "12.7 mm"
notch = "{2} mm"
plane = "stress"

[material]
E = "3 GPa"
nu = 0.3
density = "609 kg/m^3"

[fracture]
J_tip_c = "2210 J/m^2"

[bridging]
law = "linear"
sigma_c = "1 MPa"
J_B = "500 J/m^2"

[run]
max_crack_length = "{3} mm"
)",
                     width_mm, 1.2 * width_mm, 0.3 * width_mm, 0.95 * width_mm - 2.0);
}

// The 8 records, their scenes and DIR/campaign.toml; returns the synth time.
double WriteCampaign(const fs::path& dir) {
  fs::create_directories(dir);
  std::string manifest = "[campaign]\nname = \"8 synthetic CT specimens\"\nlaw = \"linear\"\n";
  double synth_s = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double width = i < 4 ? 50.0 : 100.0;
    const fs::path scene_path = dir / fmt::format("scene_w{:.0f}.toml", width);
    if (!fs::exists(scene_path)) std::ofstream(scene_path) << SceneToml(width);
    pipeline::SynthRequest synth;
    synth.scene = io::ReadSceneFile(scene_path.string());
    synth.seed = static_cast<std::uint64_t>(i + 1);
    synth.resolution = 0.25e-3;
    synth.frames = 0;
    const pipeline::SynthTest test = pipeline::MakeSyntheticTest(synth);
    synth_s += test.wall_s;
    const std::string name = fmt::format("W{:.0f}-{}", width, i + 1);
    std::ofstream(dir / (name + ".csv")) << test.record_csv;
    manifest += fmt::format("\n[[specimen]]\nname = \"{}\"\nrecord = \"{}.csv\"\nscene = \"{}\"\n",
                            name, name, scene_path.filename().string());
  }
  std::ofstream(dir / "campaign.toml") << manifest;
  return synth_s;
}

}  // namespace

int main(int argc, char** argv) {
  // --manifest DIR: only the campaign (for `mpirun ... bridgefit campaign`,
  // bench/campaign_mpi_bench.sh).
  if (argc > 2 && std::string(argv[1]) == "--manifest") {
    std::printf("8 records made in %.1f s (synth, summed): %s/campaign.toml\n",
                WriteCampaign(argv[2]), argv[2]);
    return 0;
  }
  const std::string prefix = argc > 1 ? argv[1] : "campaign_bench";
  const fs::path dir = fs::temp_directory_path() / fmt::format("bf_campaign_bench_{}", ::getpid());
  const double synth_s = WriteCampaign(dir);
  const io::CampaignManifest m = io::ReadCampaignManifest(dir / "campaign.toml");
  std::printf("8 records made in %.1f s (synth, summed)\n", synth_s);

  std::ofstream csv(prefix + ".csv");
  csv << "run, threads, profile threads per fit, wall [s], specimens fitted, sum of single fits [s], "
         "joint fit [s], joint J_B identified, joint consistent\n";
  // Specimens side by side (threads) against each fit's own profile threads:
  // with 1 profile thread per fit the speed-up is the campaign's alone; by
  // default (cores / threads) a lone fit already uses both cores.
  struct Run {
    int threads, fit_threads;
    bool joint;
  };
  double serial_wall = 0.0;
  for (const Run& run : {Run{1, 1, false}, Run{2, 1, false}, Run{1, 0, false}, Run{2, 0, false},
                         Run{2, 0, true}}) {
    const int threads = run.threads;
    const bool joint = run.joint;
    campaign::CampaignOptions options;
    options.jobs = threads;
    options.fit_threads = run.fit_threads;
    options.joint = joint;
    const campaign::CampaignResult r = campaign::RunCampaign(m, options);
    double sum = 0.0;
    int fitted = 0;
    for (const campaign::SpecimenOutcome& s : r.specimens) {
      sum += s.wall_s;
      fitted += s.ok() ? 1 : 0;
    }
    if (threads == 1) serial_wall = r.wall_s;
    const int profile_threads = run.fit_threads > 0 ? run.fit_threads : std::max(1, 2 / threads);
    const double joint_s = r.joint ? r.joint->wall_s : NAN;
    std::printf("%-6s %d thread(s), %d profile thread(s) per fit: wall %.1f s (speed-up %.2f, "
                "efficiency %.0f%%), %d of 8 fitted, single fits summed %.1f s%s\n",
                joint ? "joint" : "single", threads, profile_threads, r.wall_s, serial_wall / r.wall_s,
                100.0 * serial_wall / r.wall_s / threads, fitted, sum,
                r.joint ? fmt::format(", joint fit {:.1f} s ({}; J_B {})", joint_s,
                                      r.joint->consistency.consistent() ? "consistent" : "not consistent",
                                      r.joint->summary.J_B.identified ? "identified" : "bound")
                              .c_str()
                        : "");
    csv << fmt::format("{}, {}, {}, {:.2f}, {}, {:.2f}, {:.2f}, {}, {}\n",
                       joint ? "with joint" : "single", threads, profile_threads, r.wall_s, fitted,
                       sum, joint_s,
                       r.joint && r.joint->summary.J_B.identified ? 1 : 0,
                       r.joint && r.joint->consistency.consistent() ? 1 : 0);
  }
  fs::remove_all(dir);
  return 0;
}
