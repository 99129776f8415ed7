// Step logs as CSV, whole or streamed through a ring to files.
#include "hapticut/haptics/step_log.h"

#include <chrono>

#include "hapticut/common/line_reader.h"

namespace hapticut::haptics {

StepLogLayout StepLogLayout::of(StepLogColumns columns, const StepOutput& first) {
    StepLogLayout layout;
    layout.columns = columns;
    layout.twoHands = columns == StepLogColumns::ForceLog && first.handCount > 1;
    const bool session = columns == StepLogColumns::Session;
    layout.oriented = session || (columns == StepLogColumns::Recording && first.hand().oriented);
    layout.tools = session || (columns == StepLogColumns::Recording && first.hand().tool >= 0);
    return layout;
}

std::string StepLogLayout::header() const {
    if (columns != StepLogColumns::ForceLog)
        return std::string(oriented ? "t,x,y,z,button,qw,qx,qy,qz" : "t,x,y,z,button") + (tools ? ",tool" : "") +
               ",fx,fy,fz\n";
    std::string out = "t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,face,cut";
    out += twoHands ? ",device_x2,device_y2,device_z2,proxy_x2,proxy_y2,proxy_z2,fx2,fy2,fz2,contact2,face2\n" : "\n";
    return out;
}

void StepLogLayout::appendRow(std::string& out, const StepOutput& s) const {
    auto number = [&](double value) {
        out += ',';
        out += formatDouble(value);
    };
    auto vec = [&](const Vec3& v) {
        for (int k = 0; k < 3; ++k) number(v[k]);
    };
    auto hand = [&](const HandStep& h) {
        vec(h.device_m), vec(h.proxy_m), vec(h.force_N);
        out += h.contact ? ",1," : ",0,";
        out += std::to_string(h.face);
    };
    out += formatDouble(s.t_s);
    if (columns != StepLogColumns::ForceLog) {
        vec(s.hand().device_m);
        out += ',';
        out += static_cast<char>('0' + (s.hand().buttons & 3u));  // the main button and the second (a mark)
        if (oriented) {
            // A step without an orientation (a session's before its blade turns) reads back as none.
            const Eigen::Quaterniond q = s.hand().oriented ? s.hand().orientation : Eigen::Quaterniond(0, 0, 0, 0);
            number(q.w()), number(q.x()), number(q.y()), number(q.z());
        }
        if (tools) {
            out += ',';
            out += std::to_string(std::max(s.hand().tool, 0));
        }
        vec(s.hand().force_N);
    } else {
        hand(s.hands[0]);
        out += s.cut ? ",1" : ",0";
        if (twoHands) hand(s.hands[1]);
    }
    out += '\n';
}

std::string formatStepLog(std::span<const StepOutput> log, StepLogColumns columns) {
    const StepLogLayout layout = StepLogLayout::of(columns, log.empty() ? StepOutput{} : log.front());
    std::string out = layout.header();
    out.reserve(out.size() + log.size() * (layout.twoHands ? 300 : 160));
    for (const StepOutput& s : log) layout.appendRow(out, s);
    return out;
}

Result<std::unique_ptr<StepLogWriter>, Error> StepLogWriter::open(std::vector<Target> targets, WhenFull whenFull) {
    std::vector<File> files;
    for (Target& target : targets) {
        auto file = AtomicFile::create(target.file);
        if (!file) return unexpected(file.error());
        files.push_back(File{std::move(*file), target.columns, {}, {}});
    }
    return std::unique_ptr<StepLogWriter>(new StepLogWriter(std::move(files), whenFull));
}

StepLogWriter::StepLogWriter(std::vector<File> files, WhenFull whenFull)
    : files_(std::move(files)),
      ring_(std::make_unique<SpscQueue<StepOutput, kRingSteps>>()),
      waitWhenFull_(whenFull == WhenFull::Wait) {
    thread_ = std::thread([this] { drain(); });
}

StepLogWriter::~StepLogWriter() {
    finishing_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    // The files abandon themselves unless finish() committed them.
}

void StepLogWriter::push(const StepOutput& step) noexcept {
    while (!ring_->push(step)) {
        if (!waitWhenFull_.load(std::memory_order_relaxed)) {
            dropped_.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        std::this_thread::yield();
    }
}

void StepLogWriter::drain() {
    constexpr std::size_t kFlushBytes = 1 << 20;
    for (File& f : files_) f.buffer.reserve(kFlushBytes + 4096);
    bool headers = false;
    for (;;) {
        const bool last = finishing_.load(std::memory_order_acquire);  // read before the ring: nothing after it
        bool any = false;
        while (const std::optional<StepOutput> step = ring_->pop()) {
            any = true;
            if (!headers) {
                for (File& f : files_) {
                    f.layout = StepLogLayout::of(f.columns, *step);
                    f.buffer += f.layout.header();
                }
                headers = true;
            }
            for (File& f : files_) f.layout.appendRow(f.buffer, *step);
            rows_.fetch_add(1, std::memory_order_relaxed);
            flushBuffers(kFlushBytes);
        }
        if (last) break;
        if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!headers)
        for (File& f : files_) f.buffer += StepLogLayout::of(f.columns, StepOutput{}).header();
    flushBuffers(0);
}

void StepLogWriter::flushBuffers(std::size_t atLeast) {
    for (File& f : files_)
        if (f.buffer.size() >= atLeast && !f.buffer.empty()) {
            f.file.write(f.buffer);
            f.buffer.clear();
        }
}

std::vector<Error> StepLogWriter::finish() {
    finishing_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    std::vector<Error> errors;
    for (File& f : files_)
        if (WriteStatus error = f.file.commit()) errors.push_back(std::move(*error));
    return errors;
}

}  // namespace hapticut::haptics
