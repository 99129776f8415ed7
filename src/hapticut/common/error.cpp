// Error formatting.
#include "hapticut/common/error.h"

namespace hapticut {

std::string Error::toString() const {
    if (file.empty()) return message;
    std::string s = file.string();
    if (line > 0) s.append(":").append(std::to_string(line));
    s.append(": ").append(message);
    return s;
}

}  // namespace hapticut
