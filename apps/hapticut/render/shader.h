// GLSL programs: compiled and linked with the driver's log in the error, uniforms looked up once.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

#include <Eigen/Core>

namespace hapticut::render {

class ShaderProgram {
public:
    /// Compiles and links; on failure nothing, with `error` naming the program, the stage and the log.
    static std::optional<ShaderProgram> build(std::string_view name, const char* vertexSource,
                                              const char* fragmentSource, std::string& error);
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ~ShaderProgram();

    void use() const;
    void set(const char* uniform, const Eigen::Matrix4f& m);
    void set(const char* uniform, const Eigen::Vector3f& v);
    void set(const char* uniform, const Eigen::Vector4f& v);
    void set(const char* uniform, float value);
    void set(const char* uniform, int value);

private:
    ShaderProgram() = default;
    int location(const char* uniform);
    unsigned id_ = 0;
    std::unordered_map<std::string, int> locations_;
};

}  // namespace hapticut::render
