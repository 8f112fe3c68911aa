// libFuzzer target: arbitrary bytes as a processing recipe (JSON parse, then the recipe's
// checks); a recipe that is accepted must write back to JSON that reads to the same recipe.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "pipeline/processing_recipe.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json doc = nlohmann::json::parse(data, data + size, nullptr, false);
  if (doc.is_discarded()) return 0;
  try {
    const mocap::pipeline::ProcessingRecipe recipe = mocap::pipeline::RecipeFromJson(doc, "fuzz");
    const nlohmann::json written = mocap::pipeline::RecipeToJson(recipe);
    if (mocap::pipeline::RecipeToJson(mocap::pipeline::RecipeFromJson(written, "fuzz")) != written) std::abort();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
