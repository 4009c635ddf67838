// `bridgefit report`: HTML page with gnuplot figures from a fit file.
//   bridgefit report fit.h5 --out out/mdf_ct
//   bridgefit report fit.h5 --out out/mdf_ct --record rcurve.h5 --dic dic.csv --dic dic.h5 --truth scene.toml
//   bridgefit report fit.h5 --out out/dcb --reference-csv DCB-01.csv --reference G_I
//       --columns crack_length=CrackExt --units crack_length=mm,G_I=N/mm

#include <iostream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/csv.hpp"

#include "bridgefit/pipeline/report_file.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {

class ReportCommand final : public Command {
 public:
  const char* name() const override { return "report"; }
  const char* description() const override {
    return "HTML report (index.html + PNG figures by gnuplot) of a fit file";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("fit", fit_, "Fit file from 'bridgefit fit --out'")->required();
    sub.add_option("--out", out_, "Output folder (replaced if it exists)")->required();
    sub.add_option("--record", options_.record_h5,
                   "HDF5 with /experiment (bridgefit rcurve --out): load-displacement, crack length");
    sub.add_option("--dic", dic_files_,
                   "DIC output: the per-frame CSV (bridgefit dic --csv) and/or the HDF5 (bridgefit dic "
                   "--out: tips, crack line, openings for the evidence figures); repeat for both");
    sub.add_option("--images", options_.images_dir,
                   "Folder of the DIC images when their recorded paths do not resolve");
    sub.add_option("--reference-csv", options_.reference.csv,
                   "Record CSV holding a reference toughness column to draw against R");
    sub.add_option("--reference", options_.reference.column, "That column's header, e.g. G_I");
    sub.add_option("--columns", columns_,
                   "Reference CSV: crack_length=HEADER (as for bridgefit rcurve)");
    sub.add_option("--units", units_,
                   "Reference CSV units, e.g. crack_length=mm,G_I=N/mm (else the header's brackets)");
    sub.add_option("--truth", options_.truth_scene, "Scene TOML with the true law (synthetic tests)");
    sub.add_option("--lawfree", options_.lawfree_h5,
                   "bridgefit lawfree --out: the law-free sigma(delta) and its band over the fitted law");
    sub.add_option("--title", options_.title, "Page title");
    sub.add_option("--gnuplot", options_.gnuplot, "gnuplot executable")->default_val("gnuplot");
  }
  int Run(const CommonOptions& common) override {
    for (const std::string& file : dic_files_) {
      const std::string ext = std::filesystem::path(file).extension().string();
      std::filesystem::path& slot = ext == ".h5" || ext == ".hdf5" ? options_.dic_h5 : options_.dic_csv;
      if (!slot.empty())
        throw Error(ErrorKind::kUsage, "two DIC files of the same kind",
                    {.field = "--dic", .value = file, .expected = "one CSV and/or one HDF5 (.h5)"});
      slot = file;
    }
    if (!columns_.empty() || !units_.empty()) {
      if (!options_.reference.enabled())
        throw Error(ErrorKind::kUsage, "--columns and --units map the reference CSV: give --reference-csv and --reference",
                    {.field = "--columns, --units"});
      io::RecordColumns mapping;
      if (!columns_.empty()) io::ApplyColumnMapping(columns_, mapping);
      options_.reference.crack_length_column = mapping.crack_length;
      // Units: by quantity name (crack_length) or by the reference's header.
      for (const std::string& item : SplitComma(units_)) {
        const size_t eq = item.find('=');
        if (eq == std::string::npos)
          throw Error(ErrorKind::kUsage, "a unit mapping is NAME=UNIT", {.field = "--units", .value = item});
        std::string name = item.substr(0, eq);
        if (name == "crack_length") name = options_.reference.crack_length_column;
        options_.reference.units[name] = item.substr(eq + 1);
      }
    }
    const report::ReportSummary s = pipeline::WriteFitReport(fit_, out_, options_);
    if (common.json) {
      PrintJson({{"index_html", s.index_html.string()},
                 {"figures", s.figures},
                 {"notes", s.notes},
                 {"wall_s", s.wall_s}});
    } else {
      std::cout << s.BriefReport() << "\n";
    }
    return 0;
  }

 private:
  static std::vector<std::string> SplitComma(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size() && !text.empty()) {
      const size_t comma = text.find(',', start);
      out.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return out;
  }

  std::string fit_, out_, columns_, units_;
  std::vector<std::string> dic_files_;
  report::ReportOptions options_;
};

}  // namespace

std::unique_ptr<Command> MakeReportCommand() { return std::make_unique<ReportCommand>(); }

}  // namespace bridgefit::cli
