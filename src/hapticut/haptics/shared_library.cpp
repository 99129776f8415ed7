// dlopen with a record of every place it looked.
#include "hapticut/haptics/shared_library.h"

#include <dlfcn.h>

#include <filesystem>

namespace hapticut::haptics {

std::unique_ptr<SharedLibrary> SharedLibrary::open(const std::vector<std::string>& names, const std::vector<std::string>& folders, std::string& error) {
    std::vector<std::string> attempts;
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
            attempts.push_back(candidate + (folder.empty() ? " (system search path)" : "") + ": " + (why ? why : "not found"));
        }
    error = "could not open any of:";
    for (const std::string& a : attempts) error += "\n  " + a;
    return nullptr;
}

SharedLibrary::~SharedLibrary() {
    if (handle_) dlclose(handle_);
}

void* SharedLibrary::symbol(const char* name) const { return handle_ ? dlsym(handle_, name) : nullptr; }

}  // namespace hapticut::haptics
