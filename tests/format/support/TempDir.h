// A fresh, uniquely named folder under the system temp folder, removed with its contents.
#pragma once

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

namespace sluice::test {

/// Creates the folder on construction, removes it recursively on destruction.
class TempDir {
public:
    TempDir() {
        static std::atomic<int> s_counter{0};
        m_path = std::filesystem::temp_directory_path() /
                 ("sluice-format-test-" + std::to_string(::getpid()) + "-" +
                  std::to_string(s_counter.fetch_add(1)));
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }

    /// The folder.
    const std::filesystem::path& path() const { return m_path; }
    /// A path inside the folder.
    std::filesystem::path operator/(const std::string& name) const { return m_path / name; }
    /// Names of the entries in the folder, sorted.
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : std::filesystem::directory_iterator(m_path))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

private:
    std::filesystem::path m_path;
};

} // namespace sluice::test
