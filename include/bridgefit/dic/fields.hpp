#pragma once
// Displacement fields exported by other DIC software (one frame per file),
// read by their header names - never by column position - with units:
//
//  kCsv:    plain CSV, header "x [mm], y [mm], u [mm], v [mm]" (any length
//           unit or px, same unit for all four; optional "valid" 0/1 column).
//  kAramis: GOM Aramis/Correlate nodemap text: '#' comment lines, the last of
//           which names the ';'-separated columns ("x_undef [mm]; y_undef [mm];
//           ...; u [mm]; v [mm]; ...").
//  kDice:   DICe solution text: '***' header lines, then a comma-separated
//           table with SUBSET_ID, COORDINATE_X, COORDINATE_Y, DISPLACEMENT_X,
//           DISPLACEMENT_Y and SIGMA (-1 = failed subset); pixels.
//  kDavis:  LaVision DaVis vector text: first line
//           '#DaVis <version> 2D-vector <step> <ny> <nx> "" "<unit x>" "" "<unit y>"
//           "displacement" "<unit>"', then x, y, u, v rows.
//  kNcorr:  Ncorr's saved analysis, a MATLAB MAT file (v5/v7 or v7.3) with
//           every frame of a run (NcorrFile below).
//
// A point is failed when the file marks it (SIGMA = -1, valid = 0) or any of
// x, y, u, v is not a finite number. Each format has one reader and one
// writer here (the writers let tests write known-tip fields). Every reader
// takes the text (or a path) and throws Error(kInput) naming the file, the
// line and the column for anything it cannot read; files over
// kMaxFieldFileBytes are refused.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <cmath>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

namespace bridgefit::dic {

enum class FieldFormat { kCsv, kAramis, kDice, kDavis, kNcorr };
const char* FieldFormatName(FieldFormat format);
// "csv" | "aramis" | "dice" | "davis" | "ncorr"; throws Error(kUsage) otherwise.
FieldFormat ParseFieldFormat(const std::string& text);

inline constexpr std::size_t kMaxFieldFileBytes = std::size_t{1} << 30;  // 1 GiB

// One frame. Positions and displacements are in `unit`; the field is a
// scattered point list (nx = size, ny = 1) unless its points lie on a square lattice (ArrangeAsGrid).
struct FieldFile {
  DisplacementField field;
  std::string unit;         // "px" or a length unit as written ("mm", "m", "um", ...)
  double m_per_unit = 0;    // metres per unit; 0 for px (a scale must be given)
  FieldFormat format = FieldFormat::kCsv;
  std::size_t failed = 0;   // points the file marks failed (or non-finite)
  bool IsPixels() const { return m_per_unit == 0; }
};

// The format from the first line(s): '#DaVis' -> DaVis, '***' -> DICe,
// '#' lines with ';' columns -> Aramis, otherwise CSV.
FieldFormat DetectFieldFormat(const std::string& text);

// "px" for px/pixel(s); a length unit as written (with metres per unit);
// throws Error(kInput) naming the unit otherwise.
std::string NormalizeFieldUnit(const std::string& unit, double* m_per_unit);

// `name` is used in error messages (the file name). Text exports only (an
// Ncorr MAT file is refused with a pointer to NcorrFile / FieldFrames).
FieldFile ReadFieldText(const std::string& text, const std::string& name);
FieldFile ReadFieldFile(const std::filesystem::path& path);

// `unit` of the field: "px" or a length unit. DICe is pixel-only (Error(kUsage)
// for a field in length units).
std::string WriteFieldText(const FieldFile& field, FieldFormat format);
void WriteFieldFile(const std::filesystem::path& path, const FieldFile& field, FieldFormat format);

// Ncorr's saved analysis ("Save data" in Ncorr 1.2: a MAT v7.3 file; v5/v7
// where it was re-saved), read with matio. Frame k is
// data_dic_save.displacements(k+1): plot_u_ref_formatted and
// plot_v_ref_formatted on Ncorr's reduced grid, node (row r, column c), 0-based,
// at x = c (spacing + 1), y = r (spacing + 1) pixels of the reference image
// (0-based pixel centres, y down), times dispinfo.pixtounits in
// dispinfo.units ("pixels" -> px). Failed points: outside
// roi_ref_formatted.mask where that is a struct with a logical mask; where it
// is Ncorr's own ncorr_class_roi object (opaque to matio), the nodes with
// u = v = 0 exactly (Ncorr writes zeros outside the ROI and below the
// correlation cutoff). The whole data_dic_save is read on opening (a MAT v5
// variable is one compressed block); frames are converted one at a time.
// Throws Error(kInput) naming the file and the variable
// (e.g. "data_dic_save.dispinfo.units") for anything it cannot read.
class NcorrFile {
 public:
  explicit NcorrFile(const std::filesystem::path& path);
  ~NcorrFile();
  NcorrFile(NcorrFile&&) noexcept;
  NcorrFile& operator=(NcorrFile&&) noexcept;

  std::size_t Frames() const;
  FieldFile Frame(std::size_t k) const;           // k = 0 .. Frames()-1
  std::string FrameName(std::size_t k) const;     // "run.mat: displacements(3)"
  int MatVersion() const;                         // 5 (v5/v7) or 73
  int Spacing() const;                            // Ncorr's spacing parameter, px

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Opens an Ncorr file and converts every frame, keeping nothing: what a
// reader of the whole run touches (the CLI's child check of a v7.3 file).
void ReadEveryNcorrFrame(const std::filesystem::path& path);

// Writes frames (all in one unit, on one grid with x, y >= 0 on multiples of
// the grid step) in the Ncorr layout above: data_dic_save.displacements(k)
// with plot_u/v_ref_formatted and roi_ref_formatted.mask (a struct, not
// Ncorr's object), dispinfo.type/spacing/pixtounits/units. The pixel size is
// the grid step / (spacing + 1); a field in px must have step spacing + 1.
struct NcorrWriteOptions {
  int spacing_px = 0;  // Ncorr's spacing: grid step = spacing + 1 px
  bool v73 = true;     // MAT v7.3 (HDF5, as Ncorr saves); false: MAT v5
  // false: no roi_ref_formatted (as a reader without Ncorr's class sees
  // Ncorr's own files: failed nodes are then those with u = v = 0).
  bool roi_mask = true;
};
void WriteNcorrFile(const std::filesystem::path& path, const std::vector<FieldFile>& frames,
                    const NcorrWriteOptions& options);

// True when the file starts with a MAT v5/v7/v7.3 header (128 bytes ending
// in the endian indicator "IM"; MATLAB's text reads "MATLAB 5.0 MAT-file").
bool IsMatFile(const std::filesystem::path& path);

// The frames of field files in order, read one at a time: a text export is
// one frame, an Ncorr MAT file one frame per displacements(k).
class FieldFrames {
 public:
  explicit FieldFrames(std::vector<std::filesystem::path> files);
  ~FieldFrames();
  // The next frame and its name for messages; false after the last.
  bool Next(FieldFile* frame, std::string* name);

 private:
  std::vector<std::filesystem::path> files_;
  std::size_t file_ = 0, frame_ = 0;
  std::unique_ptr<NcorrFile> mat_;
};

// Field files from arguments: a folder (its .txt/.csv/.dat/.mat files), a
// glob or files; folders and globs in natural order ("f2" before "f10").
std::vector<std::filesystem::path> ExpandFieldArguments(const std::vector<std::string>& args);

// Points on a square lattice (x0 + i h, y0 + j h: DIC grids, FE node
// grids) arranged as a row-major grid (nx x ny), nodes the file does not
// hold added as masked (status kMasked, not read); true when arranged. A
// scattered list (a rotated lattice, unequal steps, a repeated node, fewer
// than a quarter of the nodes present) is left as it is. The readers call it:
// the J integral and the tip fit's continuum test need grid neighbours.
bool ArrangeAsGrid(DisplacementField* field);

// The bounding box of a field's valid points and their count (the box
// inverted, x0 = +inf, where none is valid).
struct FieldExtent {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  std::size_t valid = 0;
};
FieldExtent ValidExtent(const DisplacementField& field);

// The field with its rigid rotation taken out exactly (deformed positions
// turned back about their centroid; *theta the rotation, radians,
// counter-clockwise; unchanged and 0 where 1 - cos theta < 1e-7). The
// rotation is the similarity fit's (the valid points' deformed positions
// against their reference ones, least squares): a mode I field's own
// rotation, opposite on the two faces, adds at most its mean over an
// unbalanced field, whose second-order part is negligible. A specimen
// turning in its grips is no part of the crack: the small-strain gradient
// of a rotation reads as the equibiaxial strain -(1 - cos theta) (an LEFM
// field turned by 1 degree: J_ff 31.5 J/m^2 for 200, status ok), and on
// scattered points it scatters a column's normal displacement by theta x
// the column's width (3 degrees: a path through the whole field, no tip).
DisplacementField WithoutRigidRotation(const DisplacementField& field, double* theta);

// The spacing a field's points stand for: a grid's point spacing; for a
// scattered list (an irregular mesh, a 3D DIC nodemap's projected facets)
// at least the square root of the area its valid points cover (occupied
// cells of two nearest-neighbour spacings) per point: the nearest
// neighbour of jittered points is closer than their mean spacing, and
// windows sized by it held too few points (a lattice jittered by 0.2 of its
// step read a tip at 6.7 mm for 40 mm).
double FieldSpacing(const DisplacementField& field);

// A scattered field resampled onto a square lattice of `spacing` over its
// valid points' extent (the J integral needs a grid): each node the
// weighted local plane through the valid points within 1.5 spacings,
// where they lie on at least three sides of it; other nodes masked. Nodes
// within 1.5 spacings of the crack mix its faces, as subsets straddling it
// do (the crack band leaves them out). Empty (nx = 0) where the lattice
// would have fewer than 3 x 3 nodes or more than 4 per valid point.
DisplacementField ResampleOntoGrid(const DisplacementField& field, double spacing);

// Median distance between neighbouring points (the node or grid spacing),
// in the field's unit; 0 for fewer than two valid points.
double PointSpacing(const DisplacementField& field);

}  // namespace bridgefit::dic
