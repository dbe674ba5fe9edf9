// manifest.yaml (core/dataset.h: ReadDatasetManifest). The files a manifest
// names by default exist (empty) beside it, so that an input gets past the
// existence checks into the rest of the validation.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/dataset.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool referenced_files_made = [] {
    for (const char* name : {gc::kDefaultImageIndexFile, gc::kDefaultWheelEncodersFile,
                             gc::kDefaultLidarScansFile, gc::kDefaultGroundTruthFile,
                             gc::kDefaultFloorMapFile, gc::kDefaultGroundTruthExtrinsicsFile,
                             "calibration/camera.yaml", "calibration/extrinsics.yaml"}) {
      gf::WriteInput(name, "");
    }
    return true;
  }();
  (void)referenced_files_made;
  const auto manifest = gc::ReadDatasetManifest(gf::WriteInput(gc::kManifestFileName, data, size));
  if (manifest.ok()) {
    gf::FuzzCheck(manifest->Validate().ok(), "an accepted manifest passes Validate()");
  } else {
    gf::FuzzCheck(!manifest.message().empty(), "a rejected manifest has a message");
  }
  return 0;
}
