// The corpus's ghosting cases (issue 46): events that change nothing, tiny
// frames, black references.
#include "bad_input_corpus_builder.h"

namespace bounce::testing {

void ghostingCases(CorpusBuilder& /*corpus*/) {}

}  // namespace bounce::testing
