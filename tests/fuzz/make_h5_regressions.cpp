// Writes the hand-made HDF5 regression inputs in tests/fuzz/regressions/h5
// (the findings of issue 22 that the fuzzer met in forms too big to store).
// Not part of the build; run once:
//   g++ -std=c++20 tests/fuzz/make_h5_regressions.cpp -I/usr/include/hdf5/serial \
//     -L/usr/lib/x86_64-linux-gnu/hdf5/serial -lhdf5_cpp -lhdf5 -o /tmp/make_h5 &&
//   /tmp/make_h5 tests/fuzz/regressions/h5
#include <H5Cpp.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

H5::StrType Vlen() { return H5::StrType(H5::PredType::C_S1, H5T_VARIABLE); }

void StringAttribute(H5::H5Object& o, const char* key, const std::string& value) {
  H5::Attribute a = o.createAttribute(key, Vlen(), H5::DataSpace(H5S_SCALAR));
  const char* p = value.c_str();
  a.write(Vlen(), &p);
}

void NumberAttribute(H5::H5Object& o, const char* key, double value) {
  H5::Attribute a = o.createAttribute(key, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
  a.write(H5::PredType::NATIVE_DOUBLE, &value);
}

void Vector(H5::Group& g, const char* name, const std::vector<double>& v) {
  const hsize_t n = v.size();
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &n));
  d.write(v.data(), H5::PredType::NATIVE_DOUBLE);
  StringAttribute(d, "units", "N");
}

// A small valid /experiment group; `tweak` spoils one thing.
template <class F>
void Experiment(const std::string& file, F&& tweak) {
  H5::H5File f(file, H5F_ACC_TRUNC);
  H5::Group g = f.createGroup("/experiment");
  StringAttribute(g, "kind", "experiment");
  Vector(g, "displacement", {0, 1e-4, 2e-4});
  tweak(f, g);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  // A dataset that claims 1e9 doubles in a file of a few KB (never written:
  // no storage allocated). The old reader allocated 8 GB for it.
  Experiment(dir + "/dataset_claims_1e9_elements.h5", [](H5::H5File&, H5::Group& g) {
    StringAttribute(g, "source", "x.csv");
    const hsize_t n = 1'000'000'000;
    H5::DSetCreatPropList create;
    create.setAllocTime(H5D_ALLOC_TIME_LATE);
    g.createDataSet("load", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &n), create);
  });
  // The same under the element cap: 2e7 doubles claimed, none stored.
  Experiment(dir + "/dataset_claims_2e7_elements.h5", [](H5::H5File&, H5::Group& g) {
    StringAttribute(g, "source", "x.csv");
    const hsize_t n = 20'000'000;
    H5::DSetCreatPropList create;
    create.setAllocTime(H5D_ALLOC_TIME_LATE);
    g.createDataSet("load", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &n), create);
  });
  // Counts that were cast to int: 1e300, NaN, -1, 2.5.
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, double>>{{"rows_read_1e300", 1e300},
                                                   {"rows_read_nan", NAN},
                                                   {"rows_read_negative", -1.0},
                                                   {"rows_read_fraction", 2.5}}) {
    const double v = value;
    Experiment(dir + "/" + name + ".h5", [v](H5::H5File&, H5::Group& g) {
      StringAttribute(g, "source", "x.csv");
      Vector(g, "load", {0, 10, 20});
      NumberAttribute(g, "rows_read", v);
    });
  }
  // A fixed-length string attribute of width 2 holding 8 values: the
  // H5::Attribute std::string read wrote 16 bytes into a 2-byte buffer.
  Experiment(dir + "/string_attribute_8_values_of_2_bytes.h5", [](H5::H5File&, H5::Group& g) {
    Vector(g, "load", {0, 10, 20});
    const hsize_t n = 8;
    H5::StrType fixed(H5::PredType::C_S1, 2);
    H5::Attribute a = g.createAttribute("source", fixed, H5::DataSpace(1, &n));
    const char text[16] = {'a', 'b', 'c', 'd', 'e', 'f', 'g', 'h',
                           'i', 'j', 'k', 'l', 'm', 'n', 'o', 'p'};
    a.write(fixed, text);
  });
  // A number where a string is expected, and a string where a number is.
  Experiment(dir + "/source_is_a_number.h5", [](H5::H5File&, H5::Group& g) {
    NumberAttribute(g, "source", 3.0);
    Vector(g, "load", {0, 10, 20});
  });
  Experiment(dir + "/rows_read_is_a_string.h5", [](H5::H5File&, H5::Group& g) {
    StringAttribute(g, "source", "x.csv");
    StringAttribute(g, "rows_read", "many");
    Vector(g, "load", {0, 10, 20});
  });
  // A string dataset where numbers are expected.
  Experiment(dir + "/load_is_text.h5", [](H5::H5File&, H5::Group& g) {
    StringAttribute(g, "source", "x.csv");
    const hsize_t n = 3;
    H5::DataSet d = g.createDataSet("load", Vlen(), H5::DataSpace(1, &n));
    const char* p[3] = {"1", "2", "3"};
    d.write(p, Vlen());
  });
  // A dataset whose data lives in another file (external storage).
  Experiment(dir + "/load_in_external_file.h5", [](H5::H5File&, H5::Group& g) {
    StringAttribute(g, "source", "x.csv");
    const hsize_t n = 3;
    H5::DSetCreatPropList create;
    create.setExternal("/etc/hostname", 0, 24);
    g.createDataSet("load", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &n), create);
  });
  return 0;
}
