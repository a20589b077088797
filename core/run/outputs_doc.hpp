// The keys of summary.json described, for docs/outputs.md (outputs_markdown, columns.hpp).
#pragma once

#include <vector>

namespace harness {

struct KeyDoc {
  const char* key;     // top level, "pairs[].KEY" or "timing_us.KEY"
  const char* doc;     // one line
  bool varies;         // changes when the same state is reproduced (wall times, provenance)
};

const std::vector<KeyDoc>& summary_docs();

}  // namespace harness
