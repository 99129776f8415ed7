// Opening a shared library at run time and resolving its symbols, with errors that say which library,
// where it was looked for, which symbol is missing, and what to install.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace hapticut::haptics {

class SharedLibrary {
public:
    /// Tries each name in each folder (an empty folder: the system's own search, LD_LIBRARY_PATH and the
    /// loader cache). On failure nothing, and `error` names the files, every folder searched, and why any
    /// file that was found would not load (a missing dependency, the wrong architecture).
    static std::unique_ptr<SharedLibrary> open(const std::vector<std::string>& names,
                                               const std::vector<std::string>& folders, std::string& error);
    ~SharedLibrary();
    SharedLibrary(const SharedLibrary&) = delete;
    SharedLibrary& operator=(const SharedLibrary&) = delete;

    /// The address of `name`, or null.
    void* symbol(const char* name) const;
    /// Resolves `name` into `function`; false when the library lacks it.
    template <class F>
    bool resolve(const char* name, F& function) const {
        function = reinterpret_cast<F>(symbol(name));
        return function != nullptr;
    }
    const std::string& path() const { return path_; }

private:
    SharedLibrary() = default;
    void* handle_ = nullptr;
    std::string path_;
};

}  // namespace hapticut::haptics
