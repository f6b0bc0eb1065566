#pragma once
// One writer per output: two vdbfuse runs given the same -o must not both write it (one result
// would silently replace the other, and the second run's stale-temporary sweep would delete the
// first one's live temporary).
//
// The lock is an flock(2) on ".<name>.lock" beside the output, taken when the output is claimed
// and held until the process ends. The kernel releases it when the process dies in any way
// (kill -9 included), so a lock file left behind by a killed run never blocks the next one; the
// file holds the holder's PID, for the message the second run prints. A run removes its lock
// files as it ends (normal exit, or the signal thread's cleanup) while it still holds them; a run
// that opened the file just before it was removed notices (the path no longer names the file it
// locked) and tries again on the new one.
#include <string>

namespace vf {

// Locks `target` (a file or folder output) for the rest of this process. Taking a lock this
// process already holds does nothing. Throws vf::Error naming the target and the holder's PID
// when another process holds it, or naming the lock file when it cannot be created.
void lockOutputForThisRun(const std::string& target);

// Whether this process holds the lock of `target` (the stale-temporary sweep requires it).
bool holdsOutputLock(const std::string& target);

// Removes the lock files this process holds; the locks themselves last until the process ends.
// Called by removeAllPendingOutputs() and at exit.
void removeOutputLockFiles();

// ".<name>.lock", the lock file beside `target`.
std::string outputLockPath(const std::string& target);

}  // namespace vf
