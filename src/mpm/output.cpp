#include "bridgefit/mpm/output.hpp"

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::mpm {

bool RunOutputAvailable() { return true; }

struct RunWriter::Impl {
  std::filesystem::path h5_path;
  io::H5Writer writer;
  struct Frame {
    long step;
    double time;
    std::string group;
    std::size_t count;
  };
  std::vector<Frame> frames;
  explicit Impl(const std::filesystem::path& p) : h5_path(p), writer(p) {}
};

RunWriter::RunWriter(const std::filesystem::path& h5_path)
    : impl_(std::make_unique<Impl>(h5_path)) {}
RunWriter::~RunWriter() = default;

std::filesystem::path RunWriter::xdmf_path() const {
  auto p = impl_->h5_path;
  p.replace_extension(".xdmf");
  return p;
}

void RunWriter::AddFields(long step, double time, const ParticleFields& f) {
  auto& w = impl_->writer;
  const std::string g = fmt::format("/mpm/fields/step_{:08d}", step);
  const std::size_t n = f.x.size();
  std::vector<double> position(2 * n);
  for (std::size_t p = 0; p < n; ++p) {
    position[2 * p] = f.x[p];
    position[2 * p + 1] = f.y[p];
  }
  w.WriteMatrix(g + "/position", n, 2, position, "m", "particle positions (x, y)");
  w.WriteVector(g + "/ux", f.ux, "m", "displacement x");
  w.WriteVector(g + "/uy", f.uy, "m", "displacement y");
  w.WriteVector(g + "/vx", f.vx, "m/s", "velocity x");
  w.WriteVector(g + "/vy", f.vy, "m/s", "velocity y");
  w.WriteVector(g + "/sxx", f.sxx, "Pa", "stress xx");
  w.WriteVector(g + "/syy", f.syy, "Pa", "stress yy");
  w.WriteVector(g + "/sxy", f.sxy, "Pa", "stress xy");
  w.WriteVector(g + "/strain_energy_density", f.strain_energy_density, "J/m^3",
                "strain energy per unit volume");
  w.WriteAttribute(g, "time_s", time);
  w.WriteAttribute(g, "step", static_cast<double>(step));
  impl_->frames.push_back({step, time, g, n});
}

void RunWriter::Finish(const Summary& s, const Model& model, const SolverOptions& opt) {
  auto& w = impl_->writer;
  const std::string g = "/mpm/history";
  auto column = [&](auto get) {
    std::vector<double> v;
    for (const auto& h : s.history) v.push_back(get(h));
    return v;
  };
  w.WriteVector(g + "/time_s", column([](const HistorySample& h) { return h.time; }), "s");
  w.WriteVector(g + "/load_N", column([](const HistorySample& h) { return h.load; }), "N");
  w.WriteVector(g + "/displacement_m",
                column([](const HistorySample& h) { return h.displacement; }), "m",
                "prescribed load-point displacement");
  w.WriteVector(g + "/load_line_cod_m",
                column([](const HistorySample& h) { return h.load_line_cod; }), "m",
                "crack opening at the load line");
  w.WriteVector(g + "/kinetic_J", column([](const HistorySample& h) { return h.kinetic; }), "J");
  w.WriteVector(g + "/strain_J", column([](const HistorySample& h) { return h.strain; }), "J");
  w.WriteVector(g + "/external_work_J",
                column([](const HistorySample& h) { return h.external_work; }), "J");
  w.WriteVector(g + "/damping_per_s", column([](const HistorySample& h) { return h.damping; }),
                "1/s");
  for (std::size_t c = 0; c < opt.contour_cells.size(); ++c) {
    w.WriteVector(fmt::format("{}/J_{}cells_J_per_m2", g, opt.contour_cells[c]),
                  column([&](const HistorySample& h) { return h.J[c]; }), "J/m^2",
                  "contour J integral");
  }
  w.WriteAttribute("/mpm", "model", model.description);
  w.WriteAttribute("/mpm", "status", std::string(RunStatusName(s.status)));
  w.WriteAttribute("/mpm", "message", s.message);
  w.WriteAttribute("/mpm", "cell_m", model.grid.cell);
  w.WriteAttribute("/mpm", "ppc", static_cast<double>(model.ppc));
  w.WriteAttribute("/mpm", "shape", std::string(ShapeFunctionName(opt.shape)));
  w.WriteAttribute("/mpm", "scheme", std::string(UpdateSchemeName(opt.scheme)));
  w.WriteAttribute("/mpm", "cfl_factor", opt.cfl_factor);
  w.WriteAttribute("/mpm", "steps", static_cast<double>(s.steps));
  w.WriteAttribute("/mpm", "wall_s", s.wall_s);
  w.Commit();

  // XDMF 2: one Polyvertex grid per frame, in a temporal collection.
  const std::string h5_name = impl_->h5_path.filename().string();
  std::string x =
      "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"2.0\">\n <Domain>\n"
      "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& f : impl_->frames) {
    x += fmt::format("   <Grid Name=\"step {}\" GridType=\"Uniform\">\n", f.step);
    x += fmt::format("    <Time Value=\"{:.9g}\"/>\n", f.time);
    x += fmt::format(
        "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
        "NodesPerElement=\"1\"/>\n",
        f.count);
    x += fmt::format(
        "    <Geometry GeometryType=\"XY\">\n     <DataItem Dimensions=\"{} 2\" "
        "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{}:{}/position</DataItem>\n"
        "    </Geometry>\n",
        f.count, h5_name, f.group);
    for (const char* name :
         {"ux", "uy", "vx", "vy", "sxx", "syy", "sxy", "strain_energy_density"}) {
      x += fmt::format(
          "    <Attribute Name=\"{}\" AttributeType=\"Scalar\" Center=\"Node\">\n"
          "     <DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">{}:{}/{}</DataItem>\n    </Attribute>\n",
          name, f.count, h5_name, f.group, name);
    }
    x += "   </Grid>\n";
  }
  x += "  </Grid>\n </Domain>\n</Xdmf>\n";
  WriteTextFileAtomic(xdmf_path(), x);
}

}  // namespace bridgefit::mpm
