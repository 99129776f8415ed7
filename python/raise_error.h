// The library's errors as Python exceptions: hapticut.HapticutError with the file, the line and the message.
#pragma once

#include "hapticut/common/error.h"

namespace hapticut::python {

/// Sets hapticut.HapticutError(text, file, line, message) for `error` and throws to pybind11.
[[noreturn]] void raiseError(const Error& error);

}  // namespace hapticut::python
