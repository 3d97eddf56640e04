#include "medspheres/error.h"

#include <utility>

namespace medspheres {

InputError::InputError(std::string source, std::string problem)
    : Error(source + ": " + problem), source_(std::move(source)), problem_(std::move(problem)) {}

}  // namespace medspheres
