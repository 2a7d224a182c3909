// The corpus's output-folder cases (issue 46): records, links, FIFOs and
// temporary files that must never lead bounce to touch a file outside the
// folder, or one inside it that Bounce did not write.
#include "bad_input_corpus_builder.h"

namespace bounce::testing {

void outputFolderCases(CorpusBuilder& /*corpus*/) {}

}  // namespace bounce::testing
