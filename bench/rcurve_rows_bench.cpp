// R curves from long records (issue 15): a real DCB test (DCB-01, 377 rows)
// resampled to about 100,000 rows, clean and with noise (0.2 N, 1.5 um,
// 0.3 mm, seeded) and with the faults (an unload-reload cycle mid-test,
// a late glitch), through every DCB method: wall time per reduction, peak
// memory of the process, points, rows dropped by reason.
//
//   bf_rcurve_rows_bench [rows=100000] [record_out.csv]
//
// record_out.csv (optional): the noisy faulted record in the CLI's format, for
// bench/rcurve_rows_bench.sh (the load-displacement fit through `bridgefit fit`).
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/io/csv.hpp"

using namespace bridgefit;

namespace {

double PeakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kB
}

ExperimentRecord Resample(const ExperimentRecord& r, int rows, double load_noise, double d_noise,
                          double a_noise, unsigned seed) {
  const int n = static_cast<int>(r.size());
  const int per = std::max(1, (rows - 1) / (n - 1));
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  ExperimentRecord o;
  o.source = r.source + " (resampled)";
  for (int i = 0; i + 1 < n; ++i)
    for (int s = 0; s < per; ++s) {
      const double w = double(s) / per;
      auto mix = [&](const std::vector<double>& v) { return v[i] + w * (v[i + 1] - v[i]); };
      o.time.push_back(mix(r.time));
      o.load.push_back(mix(r.load) + load_noise * unit(rng));
      o.displacement.push_back(mix(r.displacement) + d_noise * unit(rng));
      o.crack_length.push_back(mix(r.crack_length) + a_noise * unit(rng));
    }
  return o;
}

void InjectFaults(ExperimentRecord& r) {
  // A full unload-reload cycle at mid-test (200 rows) and a 0.07 mm glitch late.
  const std::size_t k = r.size() / 2;
  const double C = r.displacement[k] / r.load[k];
  std::vector<double> P, d, a, t;
  for (int s = 1; s <= 200; ++s) {
    const double frac = s <= 100 ? s / 100.0 : (200 - s) / 100.0;
    d.push_back(r.displacement[k] * (1.0 - 0.95 * frac));
    P.push_back(d.back() / C);
    a.push_back(r.crack_length[k]);
    t.push_back(r.time[k]);
  }
  r.load.insert(r.load.begin() + k + 1, P.begin(), P.end());
  r.displacement.insert(r.displacement.begin() + k + 1, d.begin(), d.end());
  r.crack_length.insert(r.crack_length.begin() + k + 1, a.begin(), a.end());
  r.time.insert(r.time.begin() + k + 1, t.begin(), t.end());
  r.displacement[static_cast<std::size_t>(0.8 * r.size())] -= 7e-5;
}

experiment::RCurveOptions Options(experiment::RMethod method) {
  experiment::RCurveOptions o;
  o.method = method;
  o.specimen.type = SpecimenType::kDCB;
  o.specimen.width = 25e-3;
  o.specimen.height = 2.7e-3;
  o.specimen.length = 123e-3;
  o.specimen.notch = 37.64e-3;
  o.material.E = 19.3e9;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const int rows = argc > 1 ? std::atoi(argv[1]) : 100000;
  io::RecordColumns columns;
  io::ApplyColumnMapping("time=Time,displacement=Disp,load=Force,crack_length=CrackExt", columns);
  io::ApplyUnitMapping("time=s,displacement=mm,load=N,crack_length=mm", columns);
  const ExperimentRecord dcb =
      io::ReadRecordCsv(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/dcb_composite/DCB-01_Toughness.csv",
                        columns);
  std::printf("machine: %ld cores online; peak memory before: %.1f MiB\n",
              static_cast<long>(sysconf(_SC_NPROCESSORS_ONLN)), PeakMiB());
  std::printf("%-28s %-7s %8s %8s %9s %10s %8s\n", "record", "method", "rows", "points", "wall_ms",
              "peak_MiB", "dropped");
  struct Case {
    const char* name;
    ExperimentRecord record;
  };
  ExperimentRecord noisy = Resample(dcb, rows, 0.2, 1.5e-6, 0.3e-3, 15);
  ExperimentRecord faulted = noisy;
  InjectFaults(faulted);
  const Case cases[] = {{"resampled, clean", Resample(dcb, rows, 0, 0, 0, 1)},
                        {"resampled, noisy", noisy},
                        {"resampled, noisy + faults", faulted}};
  for (const Case& c : cases) {
    for (experiment::RMethod m : {experiment::RMethod::kMbt, experiment::RMethod::kComplianceCalibration,
                                  experiment::RMethod::kEnergy, experiment::RMethod::kEquivalentCrack}) {
      const auto start = std::chrono::steady_clock::now();
      const experiment::RCurveResult r = experiment::ComputeRCurve(c.record, Options(m));
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      std::printf("%-28s %-7s %8zu %8zu %9.1f %10.1f %8d\n", c.name, experiment::RMethodName(m),
                  c.record.size(), r.curve.size(), ms, PeakMiB(), r.DroppedTotal());
      if (m == experiment::RMethod::kMbt && &c == &cases[2])
        for (const experiment::DroppedRows& d : r.dropped)
          std::printf("    dropped %6d: %s\n", d.count, d.reason.c_str());
    }
  }
  if (argc > 2) {
    std::ofstream out(argv[2]);
    out << "time [s], load [N], displacement [mm], crack_length [mm]\n";
    for (std::size_t i = 0; i < faulted.size(); ++i)
      out << faulted.time[i] << ", " << faulted.load[i] << ", " << faulted.displacement[i] * 1e3
          << ", " << faulted.crack_length[i] * 1e3 << "\n";
    std::printf("wrote %s (%zu rows)\n", argv[2], faulted.size());
  }
  return 0;
}
