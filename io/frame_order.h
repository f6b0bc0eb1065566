#pragma once
// The order of frame files named by number, shared by every layout that numbers its files
// (7-Scenes, Replica, ScanNet, Redwood). A plain string sort reads "0.png, 1.png, 10.png, 11.png,
// 2.png" and a layout that pairs frames with poses by index then fuses a wrong scene without a
// word; two names of one number ("1.png" beside "01.png", "frame-1" beside "frame-000001") would
// fuse that frame twice and write a trajectory with two poses at one time.
#include <string>
#include <vector>

namespace vf {

// Compares two file names with every run of digits read as a number ("2" < "10"; "007" = "7"),
// the rest as text; the extension is left out. Negative, zero or positive like strcmp. Zero means
// the two name the same frame.
int compareFrameNames(const std::string& a, const std::string& b);

// Sorts `names` (file names, no folders) by compareFrameNames. Throws vf::Error naming `folder`
// and both files when two of them name the same frame.
void sortByFrameNumber(std::vector<std::string>& names, const std::string& folder);

}  // namespace vf
