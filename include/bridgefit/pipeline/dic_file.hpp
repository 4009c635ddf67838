#pragma once
// The output of `bridgefit dic` and `bridgefit crack`, its one owner: the
// per-frame CSV (crack length, tip, methods, flags) and the HDF5 /dic group
// (crack line, tips, opening profiles, fields), written and read here
// (docs/DIC.md). `rcurve --crack-length-from` and the report read through it.

#include <filesystem>
#include <string>
#include <vector>

#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/report/report_input.hpp"

namespace bridgefit::pipeline {

// `--csv`: one row per frame, lengths in mm, positions in px; with the J
// integral (result.j_integral) also J_ff [J/m^2], its spread [%], the
// domains that gave it, J_status, delta_star [mm], its uncertainty [mm] and
// delta_star_status (numbers empty where the status is not ok).
void WriteDicCsv(const std::string& path, const dic::CrackSequenceResult& result);
// `--out`: /dic (atomic: the file appears complete or not at all); with the
// J integral also /dic/J_ff [J/m^2], J_ff_spread [%], J_domains_ok,
// J_status, delta_star [m], delta_star_uncertainty [m], root_distance [m],
// delta_star_status and the attributes notch_length_m, j_elastic.
void WriteDicH5(const std::string& path, const dic::CrackSequenceResult& result,
                const dic::CrackSequenceOptions& options);

// The image and crack length [m] of each frame of a DIC CSV (NaN: no tip,
// or a length in doubt, see LeaveOutDoubtfulLengths).
struct DicCrackLengths {
  std::vector<std::string> image;
  std::vector<double> crack_length;
  std::vector<std::string> notes;  // the frames left out, and why
};
// Throws Error(kInput) naming the file and the missing column. With a flags
// column (every CSV of `dic` since 2026-11) the doubtful lengths are left out.
DicCrackLengths ReadDicCrackLengths(const std::string& path);
// The frames whose flags (one Flags() string per frame) put their length in
// doubt (dic::FlagsDoubtLength) lose it (NaN): the R curve interpolates over
// them instead of taking a length that may be off by more than its
// uncertainty. One note in frames.notes lists them with their flags. With
// fewer than two lengths not in doubt they all stay, and the note is a
// warning.
void LeaveOutDoubtfulLengths(const std::vector<std::string>& flags, DicCrackLengths& frames);

// The J-integral route's input from a dic.h5 (issue 21): per frame the
// image, crack length [m], J_ff [J/m^2] and its spread [%], delta* and its
// uncertainty [m] (NaN where the status is not "ok"), the statuses, and the
// notch's crack length [m]. Throws Error(kInput) naming the file and the
// missing dataset when the file holds no J integral (the way out: rerun dic
// with --scene S --j-integral).
struct DicJSeries {
  std::vector<std::string> image;
  std::vector<double> crack_length, J_ff, J_ff_spread_percent, delta_star, delta_star_uncertainty;
  std::vector<std::string> J_status, delta_star_status;
  // profile | at_root | near_tip | none (dic::DeltaStarMethodName); "missing"
  // in files without it.
  std::vector<std::string> delta_star_method;
  // The frame's DIC flags (";"-separated, "" when none; docs/DIC.md).
  std::vector<std::string> flags;
  // The field-wide fit's J_ff and its standard uncertainty [J/m^2]; status
  // "missing" where the file has none.
  std::vector<double> J_ff_fit, J_ff_fit_uncertainty;
  std::vector<std::string> J_fit_status;
  // The field's uniform dilatation, its standard uncertainty and 1 where it
  // was taken out of J (dic::FieldFitJResult; NaN / 0 in older files).
  std::vector<double> J_fit_dilatation, J_fit_dilatation_uncertainty, J_fit_dilatation_removed;
  double notch_length = NAN;
};
DicJSeries ReadDicJSeries(const std::filesystem::path& path);

// The report's view of a DIC run from its CSV and/or HDF5 (either may be
// empty): frames with tips, openings and why each is doubtful, the crack
// line, the images resolved on disk (recorded path, next to the DIC file, in
// `images_dir`). What could not be found goes to `notes`.
report::DicView ReadDicView(const std::filesystem::path& csv, const std::filesystem::path& h5,
                            const std::filesystem::path& images_dir,
                            std::vector<std::string>& notes);

}  // namespace bridgefit::pipeline
