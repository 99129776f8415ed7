// dlopen with a record of every place it looked.
#include "hapticut/haptics/shared_library.h"

#include <dlfcn.h>

#include <filesystem>

namespace hapticut::haptics {

std::unique_ptr<SharedLibrary> SharedLibrary::open(const std::vector<std::string>& names,
                                                   const std::vector<std::string>& folders, std::string& error) {
    std::vector<std::string> failures;  // files that exist but would not load: the reasons that matter
    std::vector<std::string> places = folders;
    if (places.empty()) places.push_back("");
    for (const std::string& folder : places)
        for (const std::string& name : names) {
            const std::string candidate = folder.empty() ? name : (std::filesystem::path(folder) / name).string();
            dlerror();
            if (void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL)) {
                auto library = std::unique_ptr<SharedLibrary>(new SharedLibrary);
                library->handle_ = handle;
                library->path_ = candidate;
                return library;
            }
            const char* why = dlerror();
            const std::string reason = why ? why : "not found";
            if (reason.find("No such file") == std::string::npos) failures.push_back(candidate + ": " + reason);
        }
    error = "could not open ";
    for (std::size_t i = 0; i < names.size(); ++i)
        error += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    error += "; looked in:";
    for (const std::string& folder : places)
        error += "\n  " +
                 (folder.empty() ? std::string("the system search path (LD_LIBRARY_PATH, the loader cache)") : folder);
    if (!failures.empty()) {
        error += "\nfound but could not load:";
        for (const std::string& f : failures) error += "\n  " + f;
    }
    return nullptr;
}

SharedLibrary::~SharedLibrary() {
    if (handle_) dlclose(handle_);
}

void* SharedLibrary::symbol(const char* name) const { return handle_ ? dlsym(handle_, name) : nullptr; }

}  // namespace hapticut::haptics
