// A stable train/test split of every catalogue's models, so that learned agents can be tested on
// objects they never saw. Per category, the models are ordered by a 64-bit FNV-1a hash of their
// id and the first 20 % (rounded, at least one of two or more) are the test split; a category
// with one model is train only. The assignment depends only on the ids in the category, so it is
// the same on every machine and in every run.
#pragma once

#include <string>
#include <vector>

#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {

enum class ModelSplit { kAll, kTrain, kTest };

/// "all" | "train" | "test"; throws InvalidArgumentError otherwise.
ModelSplit parseModelSplit(const std::string& text);
std::string toString(ModelSplit split);

/// kTrain or kTest for `id`; throws InvalidArgumentError for an id the catalogue lacks.
ModelSplit modelSplitOf(const ObjectCatalog& catalog, const std::string& id);

/// `ids` (any order) keeping those in `split` (all of them for kAll), order kept.
std::vector<std::string> idsInSplit(const ObjectCatalog& catalog,
                                    const std::vector<std::string>& ids, ModelSplit split);

}  // namespace occlusion_env
