// `bridgefit crack` as a library call (include/bridgefit/pipeline/crack_fields.hpp).

#include "bridgefit/pipeline/crack_fields.hpp"

#include <filesystem>
#include <system_error>

#include "bridgefit/dic/fields.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::pipeline {

CrackFieldsRun RunCrackFields(const CrackFieldsRequest& request) {
  const auto files = dic::ExpandFieldArguments(request.fields);
  // Ncorr v7.3 files are HDF5: each is read in a child first, with matio
  // as NcorrFile reads it (its attribute reads take libhdf5 paths the
  // generic walk does not), including files a folder or glob names
  // (fuzz_ncorr: libhdf5 crashes in H5HG_read on corrupt ones).
  // MAT v5 files too: a 584-byte header made matio allocate 2.6 GB and
  // run for minutes. The child gets 10 s plus 1 s per 10 MB of file.
  for (const auto& file : files)
    if (dic::IsMatFile(file)) {
      std::error_code ec;
      const double mb = static_cast<double>(std::filesystem::file_size(file, ec)) / 1e6;
      io::CheckH5FileInChildProcess(file, 10.0 + (ec ? 0.0 : mb / 10.0),
                                    [&file] { dic::ReadEveryNcorrFrame(file); });
    }
  CrackFieldsRun run;
  run.result = dic::AnalyzeCrackFields(files, request.options, request.settings, &run.used);
  return run;
}

}  // namespace bridgefit::pipeline
