// The corpus's viewer-script, compare and settings cases (issue 46).
#include "bad_input_corpus_builder.h"

namespace bounce::testing {

void scriptAndCompareCases(CorpusBuilder& /*corpus*/) {}

}  // namespace bounce::testing
