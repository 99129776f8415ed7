// The one writer of what the loop did, step by step, as CSV: the force log and the replayable recording,
// formatted whole (formatStepLog) or streamed to files as the loop runs (StepLogWriter).
#pragma once

#include <atomic>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/common/spsc_queue.h"
#include "hapticut/common/text_file.h"
#include "hapticut/haptics/haptic_loop.h"

namespace hapticut::haptics {

enum class StepLogColumns {
    /// t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,face,cut (cut: 1 when the
    /// scalpel changed the mesh in that step); with two hands the second hand's columns follow, suffixed 2.
    ForceLog,
    /// t,x,y,z,button[,qw,qx,qy,qz][,tool],fx,fy,fz: the first hand's device path, readable as a
    /// trajectory (with the stylus's orientation when its device reports one, and the tool in hand when
    /// HandStep::tool says), with the forces it felt.
    Recording,
    /// t,x,y,z,button,qw,qx,qy,qz,tool,fx,fy,fz: a recording with every column from the first row, so
    /// that a blade turned later in the session is kept: 0,0,0,0 while the device reports no orientation.
    Session,
};

/// The CSV's columns, whose choice depends on the first step (how many hands, whether oriented).
struct StepLogLayout {
    StepLogColumns columns = StepLogColumns::ForceLog;
    bool twoHands = false, oriented = false, tools = false;

    static StepLogLayout of(StepLogColumns columns, const StepOutput& first);
    std::string header() const;
    /// Appends the step's row; numbers round-trip exactly.
    void appendRow(std::string& out, const StepOutput& step) const;
};

/// Every step of `log` as CSV with those columns.
std::string formatStepLog(std::span<const StepOutput> log, StepLogColumns columns);

/// Streams the steps of a run of any length to CSV files in constant memory. The stepping thread
/// hands each step to a lock-free ring (push: no allocation, no lock, no I/O); a thread of the writer
/// drains it into the files. Each file is written beside its target and replaces it at finish(), so an
/// interrupted or failed run leaves no half-written log.
class StepLogWriter {
public:
    struct Target {
        std::filesystem::path file;
        StepLogColumns columns;
    };
    /// What push() does when the ring is full: wait for the writer (simulated time, where every step
    /// must reach the file), or drop the step and count it (real time, where the loop must not wait).
    enum class WhenFull { Wait, Drop };

    /// Creates the temporary files; an error (naming the file) when one cannot be written.
    static Result<std::unique_ptr<StepLogWriter>, Error> open(std::vector<Target> targets, WhenFull whenFull);
    ~StepLogWriter();  // abandons the files unless finish() ran
    StepLogWriter(const StepLogWriter&) = delete;
    StepLogWriter& operator=(const StepLogWriter&) = delete;

    /// From the one stepping thread.
    void push(const StepOutput& step) noexcept;
    /// Lets the writer drain the ring, then replaces each target; the errors of the files that failed.
    std::vector<Error> finish();
    /// The rows written so far to each file, and the steps dropped because the ring was full.
    long rowsWritten() const { return rows_.load(std::memory_order_relaxed); }
    long droppedSteps() const { return dropped_.load(std::memory_order_relaxed); }
    void setWhenFull(WhenFull whenFull) { waitWhenFull_.store(whenFull == WhenFull::Wait); }

    /// Steps the ring holds: 8 s at 1 kHz, for a writer held up by a slow disk.
    static constexpr std::size_t kRingSteps = 8192;

private:
    struct File {
        AtomicFile file;
        StepLogColumns columns;
        StepLogLayout layout;
        std::string buffer;
    };
    StepLogWriter(std::vector<File> files, WhenFull whenFull);
    void drain();
    void flushBuffers(std::size_t atLeast);

    std::vector<File> files_;
    std::unique_ptr<SpscQueue<StepOutput, kRingSteps>> ring_;
    std::atomic<bool> waitWhenFull_, finishing_{false};
    std::atomic<long> rows_{0}, dropped_{0};
    std::thread thread_;
};

}  // namespace hapticut::haptics
