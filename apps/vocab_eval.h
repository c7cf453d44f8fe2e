// `sgslam vocab eval`: how well a vocabulary retrieves places on a sequence with
// ground truth. Every --every-th frame is a view; a view whose ground-truth
// frustum shares at least 30 % of its depth samples with a view at least
// --min-gap seconds older is a revisit. Reported: recall@5 (revisits whose five
// best-scoring older views include such a view) and the share of queries whose
// best-scoring older view shares less than 1 % (a wrong place), over all queries
// and over the revisits.
#pragma once

#include <string>

#include "sgslam/vocab/vocabulary.h"

namespace sgslam::app {

struct VocabEvalArgs {
  std::string vocabulary, dataset;
  int every = 10;
  double min_gap_s = 10;
};

struct VocabEvalResult {
  int views = 0, queries = 0, revisits = 0, hits_at5 = 0, false_top1 = 0;
  int false_top1_revisits = 0;  // revisits whose best older view shares under 1 %
};

VocabEvalResult EvaluateVocabulary(const VocabEvalArgs& args);
std::string FormatVocabEval(const VocabEvalResult& result);

}  // namespace sgslam::app
