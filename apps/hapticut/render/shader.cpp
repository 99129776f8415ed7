// GLSL compile and link with readable errors.
#include "render/shader.h"

#include <epoxy/gl.h>

#include <utility>
#include <vector>

namespace hapticut::render {

namespace {

std::string infoLog(GLuint object, bool program) {
    GLint length = 0;
    program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)));
    program ? glGetProgramInfoLog(object, length, nullptr, log.data())
            : glGetShaderInfoLog(object, length, nullptr, log.data());
    return std::string(log.data());
}

GLuint compile(GLenum stage, const char* source, std::string_view name, std::string& error) {
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        error = std::string(name) + (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                " shader does not compile: " + infoLog(shader, false);
        glDeleteShader(shader);
        return 0;
    }
    return shader;
}

}  // namespace

std::optional<ShaderProgram> ShaderProgram::build(std::string_view name, const char* vertexSource,
                                                  const char* fragmentSource, std::string& error) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertexSource, name, error);
    if (!vs) return std::nullopt;
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragmentSource, name, error);
    if (!fs) {
        glDeleteShader(vs);
        return std::nullopt;
    }
    ShaderProgram p;
    p.id_ = glCreateProgram();
    glAttachShader(p.id_, vs);
    glAttachShader(p.id_, fs);
    glLinkProgram(p.id_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(p.id_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        error = std::string(name) + " program does not link: " + infoLog(p.id_, true);
        return std::nullopt;
    }
    return p;
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : id_(std::exchange(other.id_, 0)), locations_(std::move(other.locations_)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    std::swap(id_, other.id_);
    std::swap(locations_, other.locations_);
    return *this;
}

ShaderProgram::~ShaderProgram() {
    if (id_) glDeleteProgram(id_);
}

void ShaderProgram::use() const { glUseProgram(id_); }

int ShaderProgram::location(const char* uniform) {
    auto it = locations_.find(uniform);
    if (it == locations_.end()) it = locations_.emplace(uniform, glGetUniformLocation(id_, uniform)).first;
    return it->second;
}

void ShaderProgram::set(const char* uniform, const Eigen::Matrix4f& m) {
    glUniformMatrix4fv(location(uniform), 1, GL_FALSE, m.data());
}
void ShaderProgram::set(const char* uniform, const Eigen::Vector3f& v) { glUniform3fv(location(uniform), 1, v.data()); }
void ShaderProgram::set(const char* uniform, const Eigen::Vector4f& v) { glUniform4fv(location(uniform), 1, v.data()); }
void ShaderProgram::set(const char* uniform, float value) { glUniform1f(location(uniform), value); }
void ShaderProgram::set(const char* uniform, int value) { glUniform1i(location(uniform), value); }

}  // namespace hapticut::render
