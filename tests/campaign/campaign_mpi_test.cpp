// Campaigns over MPI ranks (issue 20; registered only with BRIDGEFIT_MPI).
// Oracles: the serial run (`--jobs 1`, no MPI) is the truth, and the same
// manifest on 1, 2 and 3 ranks must give its numbers bit for bit (a fit does
// not depend on the rank or thread that runs it): every specimen's estimates
// and intervals, the statistics, the verdicts, the campaign.h5 datasets,
// each specimen's fit file, and the joint fit (--joint), whose work is dealt
// over the ranks: its estimates, profile intervals and test. A specimen whose record is corrupt
// fails alone on whichever rank ran it; a rank killed mid-campaign ends the job non-zero with no
// output; a manifest fault is reported once, by rank 0. The same for
// `bridgefit design` (DesignMpi.*): its forward runs dealt over the ranks.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::campaign {
namespace {

namespace fs = std::filesystem;
const fs::path kSample = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples" / "mdf_ct";

struct ShellRun {
  int exit_code = -1;
  std::string out, err;
};

// A shell command line; stderr captured through a file.
ShellRun Shell(const std::string& command, const fs::path& err_path) {
  ShellRun run;
  FILE* pipe = ::popen((command + " 2>'" + err_path.string() + "'").c_str(), "r");
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
    run.out.append(buffer, n);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_path);
  std::stringstream text;
  text << err.rdbuf();
  run.err = text.str();
  return run;
}

// mpirun for the tests: root in CI, 2 cores for 3 ranks (Open MPI's
// variables; other MPIs ignore them), shared memory without ptrace (containers).
std::string Mpirun(int ranks) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_btl_vader_single_copy_mechanism=none '" +
         std::string(BRIDGEFIT_MPIEXEC) + "' -n " + std::to_string(ranks) + " '" + BRIDGEFIT_CLI +
         "' ";
}

// Three specimens of the MDF CT sample: the record, its exact twin, and a
// corrupt record second (on 2 and 3 ranks another rank than 0 runs it).
// With profiles: the intervals are compared too (the serial run's fits have
// 2 profile threads, each rank's 1).
struct Campaign {
  fs::path dir = fs::temp_directory_path() / ("bf_campaign_mpi_" + std::to_string(::getpid()));
  fs::path manifest = dir / "c.toml";
  Campaign() {
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(kSample / "scene.toml", dir / "scene.toml");
    fs::copy_file(kSample / "record.csv", dir / "a.csv");
    fs::copy_file(kSample / "record_exact.csv", dir / "b.csv");
    std::ofstream(dir / "broken.csv") << "time [s], load [N]\nnot, numbers\n";
    std::ofstream(manifest) << "[campaign]\nscene = \"scene.toml\"\nlaw = \"linear\"\n"
                               "resolution = \"1 mm\"\nprofile = true\n"
                               "[[specimen]]\nname = \"A\"\nrecord = \"a.csv\"\n"
                               "[[specimen]]\nname = \"broken\"\nrecord = \"broken.csv\"\n"
                               "[[specimen]]\nname = \"B\"\nrecord = \"b.csv\"\n";
  }
  ~Campaign() { fs::remove_all(dir); }
  // `bridgefit campaign` with `launcher` in front (empty: serial) into dir/out.
  ShellRun RunCli(const std::string& launcher, const std::string& out,
                  const std::string& flags) const {
    const std::string cli = launcher.empty() ? std::string("'") + BRIDGEFIT_CLI + "' " : launcher;
    return Shell(cli + "campaign '" + manifest.string() + "' --out '" + (dir / out).string() +
                     "' --json " + flags,
                 dir / (out + ".err"));
  }
};

// The result without what may differ between runs: wall times, threads,
// ranks (and the rank that ran a specimen), the output folder.
nlohmann::json Comparable(nlohmann::json j) {
  if (j.is_object()) {
    for (const char* key : {"wall_s", "jobs", "ranks", "rank", "out"}) j.erase(key);
    for (auto& [key, value] : j.items()) value = Comparable(value);
  } else if (j.is_array()) {
    for (auto& value : j) value = Comparable(value);
  }
  return j;
}

// Bit for bit, NaN equal to NaN.
bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// summary.csv without its wall-time column (the fourth).
std::string WithoutWallColumn(const fs::path& csv) {
  std::ifstream in(csv);
  std::string out, line;
  while (std::getline(in, line)) {
    std::size_t at = 0;
    for (int comma = 0; comma < 3 && at != std::string::npos; ++comma) at = line.find(',', at + 1);
    const std::size_t end = line.find(',', at + 1);
    out += line.substr(0, at) + line.substr(end) + "\n";
  }
  return out;
}

TEST(CampaignMpi,
     OneTwoAndThreeRanksGiveTheSerialResultAndJointFitBitForBitAndTheCorruptRecordFailsAlone) {
  const Campaign c;
  const ShellRun serial = c.RunCli("", "serial", "--jobs 1 --joint");
  ASSERT_EQ(serial.exit_code, 1) << serial.err;  // one specimen failed
  const nlohmann::json truth = nlohmann::json::parse(serial.out);
  ASSERT_EQ(truth["specimens"].size(), 3u);
  ASSERT_TRUE(truth["specimens"][0]["ok"].get<bool>()) << serial.out;
  ASSERT_TRUE(truth["specimens"][2]["ok"].get<bool>()) << serial.out;
  ASSERT_FALSE(truth["specimens"][1]["ran"].get<bool>());
  ASSERT_FALSE(truth["joint"].contains("error")) << truth["joint"];
  const io::H5Reader truth_h5(c.dir / "serial" / "campaign.h5");
  // --joint on 1, 2 and 3 ranks: the joint fit's starts, fits alone and
  // profiles dealt over the ranks (on 2 ranks, 3 profiles: 2 on rank 0, 1 on
  // rank 1). On 3, B ran on rank 2, so ranks 0 and 1 read its input again.
  // Once without --joint (the specimens alone, nothing shared back).
  for (const auto& [ranks, joint] : {std::pair{1, true}, {2, true}, {3, true}, {2, false}}) {
    SCOPED_TRACE(std::to_string(ranks) + " rank(s)" + (joint ? ", --joint" : ""));
    const std::string out = "ranks" + std::to_string(ranks) + (joint ? "_joint" : "");
    const ShellRun mpi = c.RunCli(Mpirun(ranks), out, joint ? "--joint" : "--jobs 1");
    EXPECT_EQ(mpi.exit_code, 1) << mpi.err;
    nlohmann::json got = nlohmann::json::parse(mpi.out);
    EXPECT_EQ(got["ranks"].get<int>(), ranks);
    nlohmann::json want = truth;
    if (!joint) want.erase("joint"), got.erase("joint");
    EXPECT_EQ(Comparable(got), Comparable(want)) << mpi.out;
    if (joint) {
      EXPECT_NE(mpi.err.find(ranks > 1 ? "joint fit of 2 converged specimens on " +
                                             std::to_string(ranks) + " ranks"
                                       : "joint fit of 2 converged specimens ..."),
                std::string::npos)
          << mpi.err;
      std::ifstream a(c.dir / out / "joint.csv"), b(c.dir / "serial" / "joint.csv");
      EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}),
                std::string(std::istreambuf_iterator<char>(b), {}));
    }
    EXPECT_NE(got["specimens"][1]["error"].get<std::string>().find("broken.csv"),
              std::string::npos);
    // The failure is reported on the rank that ran it, the output by rank 0.
    if (ranks > 1) {
      EXPECT_NE(mpi.err.find("rank 1: [2/3] broken: started"), std::string::npos) << mpi.err;
    }
    EXPECT_NE(mpi.err.find("warning: specimen 'broken' failed"), std::string::npos) << mpi.err;

    const fs::path dir = c.dir / out;
    EXPECT_EQ(WithoutWallColumn(dir / "summary.csv"),
              WithoutWallColumn(c.dir / "serial" / "summary.csv"));
    std::ifstream a(dir / "statistics.csv"), b(c.dir / "serial" / "statistics.csv");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}),
              std::string(std::istreambuf_iterator<char>(b), {}));
    EXPECT_FALSE(fs::exists(dir / "specimens" / "broken.h5"));
    const io::H5Reader h5(dir / "campaign.h5");
    EXPECT_EQ(h5.ReadNumberAttribute("/campaign", "ranks"), ranks);
    if (joint) {
      for (const char* attribute : {"likelihood_ratio", "p_value"})
        EXPECT_TRUE(SameBits({h5.ReadNumberAttribute("/campaign/joint", attribute)},
                             {truth_h5.ReadNumberAttribute("/campaign/joint", attribute)}))
            << attribute;
    }
    EXPECT_EQ(h5.ReadStrings("/campaign/specimen_status"),
              truth_h5.ReadStrings("/campaign/specimen_status"));
    for (const char* p : {"sigma_c", "J_B", "delta_c", "J_tip_c"}) {
      const std::string g = std::string("/campaign/statistics/") + p;
      for (const char* d : {"/value", "/lower_bound", "/ci95_low", "/ci95_high"})
        EXPECT_TRUE(SameBits(h5.ReadVector(g + d), truth_h5.ReadVector(g + d))) << g << d;
      for (const char* attribute : {"mean", "sd", "median", "campaign_lower_bound"})
        EXPECT_TRUE(SameBits({h5.ReadNumberAttribute(g, attribute)},
                             {truth_h5.ReadNumberAttribute(g, attribute)}))
            << g << " " << attribute;
      // The joint fit's estimate and interval, bit for bit.
      const std::string jg = std::string("/campaign/joint/parameters/") + p;
      if (joint) {
        for (const char* attribute : {"value", "ci95_low", "ci95_high", "lower_bound"})
          EXPECT_TRUE(SameBits({h5.ReadNumberAttribute(jg, attribute)},
                               {truth_h5.ReadNumberAttribute(jg, attribute)}))
              << jg << " " << attribute;
      }
      // Each specimen's fit file, as copied into campaign.h5 (B ran on
      // another rank with 2 and 3 ranks).
      for (const char* s : {"A", "B"}) {
        const std::string f = std::string("/specimens/") + s + "/fit/parameters/" + p;
        ASSERT_TRUE(h5.Exists(f)) << f;
        for (const char* attribute : {"value", "ci95_low", "ci95_high", "lower_bound"})
          EXPECT_TRUE(SameBits({h5.ReadNumberAttribute(f, attribute)},
                               {truth_h5.ReadNumberAttribute(f, attribute)}))
              << f << " " << attribute;
      }
    }
  }
}

// A rank killed while fitting (a lost node): mpirun ends the job, exit code
// not 0, and rank 0 has written nothing (it writes only after every rank's
// results are in).
TEST(CampaignMpi, AKilledRankEndsTheJobNonZeroWithNoOutput) {
  const Campaign c;
  const fs::path out = c.dir / "killed", err = c.dir / "killed.err";
  // On 3 ranks rank 2 runs B: killed (SIGKILL) once it has started.
  std::ofstream(c.dir / "kill.sh")
      << Mpirun(3) << "campaign '" << c.manifest.string() << "' --out '" << out.string()
      << "' >/dev/null 2>'" << err.string() << "' &\n"
      << "job=$!\n"
      << "for i in $(seq 600); do grep -q 'rank 2: \\[3/3\\] B: started' '" << err.string()
      << "' && break; sleep 0.05; done\n"
      << "for p in $(pgrep -P $job); do\n"
      << "  tr '\\0' '\\n' < /proc/$p/environ | grep -qx OMPI_COMM_WORLD_RANK=2 && kill -9 $p\n"
      << "done\n"
      << "wait $job\necho $?\n";
  const ShellRun run = Shell("bash '" + (c.dir / "kill.sh").string() + "'", c.dir / "kill.err");
  std::ifstream err_in(err);
  const std::string text((std::istreambuf_iterator<char>(err_in)), {});
  ASSERT_FALSE(run.out.empty()) << run.err;
  ASSERT_NE(text.find("rank 2: [3/3] B: started"), std::string::npos) << text;
  // A machine too loaded to catch B's fit (about 1 s) proves nothing.
  if (text.find("rank 2: [1 done of 1] B") != std::string::npos)
    GTEST_SKIP() << "rank 2 finished B before the kill: not a lost rank";
  EXPECT_NE(std::stoi(run.out), 0) << text;
  EXPECT_FALSE(fs::exists(out)) << text;
}

// A joint fit that cannot run (one specimen converged) fails the same way on
// every rank: the campaign's joint error as without MPI, no rank left waiting.
TEST(CampaignMpi, AJointFitThatCannotRunIsTheSerialRunsJointErrorOnTwoRanks) {
  const Campaign c;
  std::ofstream(c.manifest) << "[campaign]\nscene = \"scene.toml\"\nlaw = \"linear\"\n"
                               "resolution = \"1 mm\"\n"
                               "[[specimen]]\nname = \"A\"\nrecord = \"a.csv\"\n"
                               "[[specimen]]\nname = \"broken\"\nrecord = \"broken.csv\"\n";
  const ShellRun serial = c.RunCli("", "serial", "--jobs 1 --joint");
  const nlohmann::json truth = nlohmann::json::parse(serial.out);
  ASSERT_TRUE(truth["joint"].contains("error")) << serial.out;
  ASSERT_NE(truth["joint"]["error"].get<std::string>().find("two or more"), std::string::npos)
      << truth["joint"];
  const ShellRun mpi = c.RunCli(Mpirun(2), "ranks2", "--joint");
  EXPECT_EQ(mpi.exit_code, serial.exit_code) << mpi.err;
  const nlohmann::json got = nlohmann::json::parse(mpi.out);
  EXPECT_EQ(got["joint"], truth["joint"]);
  EXPECT_TRUE(fs::exists(c.dir / "ranks2" / "summary.csv"));
}

// A missing record: every rank finds it before any work; rank 0 reports it
// once, naming the manifest line; nothing is written.
TEST(CampaignMpi, AManifestFaultIsReportedOnceByRankZeroAndNothingIsWritten) {
  const Campaign c;
  std::ofstream(c.manifest, std::ios::app) << "[[specimen]]\nname = \"C\"\nrecord = \"gone.csv\"\n";
  const ShellRun run = c.RunCli(Mpirun(2), "fault", "");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  const std::size_t first = run.err.find("gone.csv");
  ASSERT_NE(first, std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("gone.csv", first + 1), std::string::npos) << run.err;  // once
  EXPECT_NE(run.err.find("c.toml:"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(c.dir / "fault"));
}


// `mpirun -n N bridgefit design` (issue 20): the design's forward runs (size x
// law of the fit's region) dealt over the ranks, gathered bit for bit; rank 0
// alone prints and writes the chart. Oracle: the serial run's JSON (less its
// wall time and chart path) and chart table, byte for byte, on 1, 2 and 3
// ranks; by both routes (a fit file with its 2x2 region: 5 laws x 4 sizes =
// 20 runs, so every rank owns runs of several laws; a scene: 5 sizes).
struct DesignRuns {
  fs::path dir = fs::temp_directory_path() / ("bf_design_mpi_" + std::to_string(::getpid()));
  DesignRuns() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~DesignRuns() { fs::remove_all(dir); }
  ShellRun Run(const std::string& launcher, const std::string& args, const std::string& name) const {
    const std::string cli = launcher.empty() ? std::string("'") + BRIDGEFIT_CLI + "' " : launcher;
    return Shell(cli + "design " + args, dir / (name + ".err"));
  }
};

nlohmann::json DesignComparable(const std::string& out) {
  nlohmann::json j = nlohmann::json::parse(out);
  j.erase("wall_s");
  j.erase("chart");
  return j;
}

std::string FileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(DesignMpi, OneTwoAndThreeRanksGiveTheSerialDesignBitForBitByBothRoutes) {
  const DesignRuns d;
  const fs::path fit = d.dir / "fit.h5";
  const ShellRun fitted = Shell(std::string("'") + BRIDGEFIT_CLI + "' fit '" +
                                    (kSample / "record.csv").string() + "' --scene '" +
                                    (kSample / "scene.toml").string() +
                                    "' --fit-to load-displacement --resolution 1mm --no-profile "
                                    "--quiet --out '" +
                                    fit.string() + "'",
                                d.dir / "fit.err");
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  // Elements of 1% of W: a coarse design, to keep the test short.
  const std::string fit_args =
      "'" + fit.string() + "' --size 60mm:120mm:20mm --grid 2 --resolution-fraction 0.01 --json";
  const std::string scene_args = "'" + (kSample / "scene.toml").string() +
                                 "' --sigma-c 1MPa --size 30mm:110mm:20mm "
                                 "--resolution-fraction 0.01 --json";
  const ShellRun fit_serial =
      d.Run("", fit_args + " --chart '" + (d.dir / "chart_serial").string() + "'", "fit_serial");
  ASSERT_EQ(fit_serial.exit_code, 0) << fit_serial.err;
  const nlohmann::json fit_truth = DesignComparable(fit_serial.out);
  ASSERT_EQ(fit_truth["region_laws"].size(), 4u) << fit_serial.out;
  ASSERT_EQ(fit_truth["sizes"].size(), 4u) << fit_serial.out;
  const ShellRun scene_serial = d.Run("", scene_args, "scene_serial");
  ASSERT_EQ(scene_serial.exit_code, 0) << scene_serial.err;
  const nlohmann::json scene_truth = DesignComparable(scene_serial.out);
  ASSERT_EQ(scene_truth["sizes"].size(), 5u) << scene_serial.out;
  // Not a trivial answer: some sizes identify J_B, some do not.
  int identify = 0;
  for (const auto& s : scene_truth["sizes"]) identify += s["identifies"].get<bool>();
  ASSERT_GT(identify, 0) << scene_serial.out;
  ASSERT_LT(identify, 5) << scene_serial.out;
  int region_identify = 0;
  for (const auto& s : fit_truth["sizes"]) region_identify += s["region_identify"].get<int>();
  ASSERT_GT(region_identify, 0) << fit_serial.out;
  for (int ranks : {1, 2, 3}) {
    SCOPED_TRACE(std::to_string(ranks) + " rank(s)");
    const std::string chart = "chart_ranks" + std::to_string(ranks);
    const ShellRun f = d.Run(Mpirun(ranks), fit_args + " --chart '" + (d.dir / chart).string() + "'",
                             "fit_ranks" + std::to_string(ranks));
    ASSERT_EQ(f.exit_code, 0) << f.err;
    // Rank 0 alone prints: exactly one JSON object on stdout.
    EXPECT_EQ(DesignComparable(f.out).dump(), fit_truth.dump()) << f.out;
    EXPECT_EQ(FileText(d.dir / chart / "onset.dat"), FileText(d.dir / "chart_serial" / "onset.dat"));
    if (ranks > 1) {
      EXPECT_NE(f.err.find("20 forward runs dealt over " + std::to_string(ranks) + " MPI ranks"),
                std::string::npos)
          << f.err;
    }
    const ShellRun s = d.Run(Mpirun(ranks), scene_args, "scene_ranks" + std::to_string(ranks));
    ASSERT_EQ(s.exit_code, 0) << s.err;
    EXPECT_EQ(DesignComparable(s.out).dump(), scene_truth.dump()) << s.out;
  }
}

// An input fault found on every rank is reported once, by rank 0, and the
// job ends with the serial run's exit code.
TEST(DesignMpi, AnInputFaultIsReportedOnceByRankZero) {
  const DesignRuns d;
  const std::string args = "'" + (kSample / "scene.toml").string() + "' --size 50mm:40mm:10mm";
  const ShellRun serial = d.Run("", args, "serial");
  ASSERT_EQ(serial.exit_code, 2) << serial.err;
  const ShellRun mpi = d.Run(Mpirun(2), args, "ranks2");
  EXPECT_EQ(mpi.exit_code, 2) << mpi.err;
  const std::size_t first = mpi.err.find("bad size range");
  ASSERT_NE(first, std::string::npos) << mpi.err;
  EXPECT_EQ(mpi.err.find("bad size range", first + 1), std::string::npos) << mpi.err;  // once
  EXPECT_TRUE(mpi.out.empty()) << mpi.out;
}

// A specimen with its images ([specimen.dic]) run on rank 1 of 2 (issue 19
// with 20): its DIC file, notes and frame crack lengths travel to rank 0, and
// with --joint to every rank, which rebuilds its record from the frames: the
// JSON (the joint fit too) and the DIC datasets in campaign.h5 equal the
// serial run's.
TEST(CampaignMpi, ASpecimensDicOnAnotherRankGivesTheSerialResultWithTheJointFit) {
  const Campaign c;
  fs::create_directory_symlink(kSample / "images", c.dir / "images");
  std::ofstream(c.manifest) << "[campaign]\nscene = \"scene.toml\"\nlaw = \"linear\"\n"
                               "resolution = \"1 mm\"\nprofile = false\n"
                               "[[specimen]]\nname = \"B\"\nrecord = \"b.csv\"\n"
                               "[[specimen]]\nname = \"MDF\"\nrecord = \"a.csv\"\n"
                               "[specimen.dic]\nimages = \"images\"\n"
                               // 20 px off the crack: every frame flagged, so notes travel
                               "crack_line = [\"0 px\", \"170 px\", \"399 px\", \"170 px\"]\n"
                               "scale = \"0.15 mm/px\"\noffset = \"20 mm\"\n";
  const ShellRun serial = c.RunCli("", "serial", "--jobs 1 --joint");
  ASSERT_EQ(serial.exit_code, 0) << serial.err;
  const nlohmann::json truth = nlohmann::json::parse(serial.out);
  ASSERT_TRUE(truth["specimens"][1]["ok"].get<bool>()) << serial.out;
  ASSERT_FALSE(truth["specimens"][1]["notes"].empty()) << serial.out;
  ASSERT_FALSE(truth["joint"].contains("error")) << truth["joint"];
  const ShellRun mpi = c.RunCli(Mpirun(2), "ranks2", "--jobs 1 --joint");
  ASSERT_EQ(mpi.exit_code, 0) << mpi.err;
  EXPECT_NE(mpi.err.find("rank 1: [2/2] MDF: started"), std::string::npos) << mpi.err;
  EXPECT_EQ(Comparable(nlohmann::json::parse(mpi.out)), Comparable(truth)) << mpi.out;
  const io::H5Reader a(c.dir / "serial" / "campaign.h5"), b(c.dir / "ranks2" / "campaign.h5");
  for (const char* d : {"crack_length", "crack_length_raw", "crack_length_uncertainty"}) {
    const std::string path = std::string("/specimens/MDF/dic/") + d;
    ASSERT_TRUE(b.Exists(path)) << path;
    EXPECT_TRUE(SameBits(a.ReadVector(path), b.ReadVector(path))) << path;
  }
  EXPECT_TRUE(SameBits(a.ReadVector("/specimens/MDF/experiment/crack_length"),
                       b.ReadVector("/specimens/MDF/experiment/crack_length")));
}

}  // namespace
}  // namespace bridgefit::campaign
