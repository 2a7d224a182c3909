// The corpus's memory cases (issue 46): small files that ask for gigabytes
// (huge images, repeated URIs, accessor counts, sparse files) must be
// refused or loaded within a bound, before the memory is spent.
#include "bad_input_corpus_builder.h"

namespace bounce::testing {

void sceneMemoryCases(CorpusBuilder& /*corpus*/) {}

}  // namespace bounce::testing
