#pragma once
// Results appear whole or not at all, and never mixed with another run's: the output folder is checked
// when the run starts (before any work); images are written under temporary names as they come (so a
// long run holds no frame's pictures after the frame), other files are kept in memory; only when
// everything has succeeded are they all renamed into place, the files they replace kept aside until
// every rename has succeeded (and put back if one fails). A run that fails or is abandoned before its
// commit removes its temporary files and any folder it made for them.
//
// A folder a run owns (render's) holds that run's outputs alone: the files an earlier pp5sim run
// listed in the folder's manifest (.pp5sim-outputs) and this one does not write are removed, as are
// temporary files a killed run left behind. Folders several processes share (a sweep's shards) are
// not owned, and keep what others wrote.

#include "frontends/image_io.h"

#include <filesystem>
#include <string>
#include <vector>

namespace pp5 {

// Throws InputError(path, option, why) unless `directory` is a folder this process can write, or can
// be made as one (its nearest existing ancestor is a writable folder).
void check_output_folder(const std::filesystem::path& directory, const std::string& option);
// The same for a file to be written at `file` (its folder, and that it is not itself a folder).
void check_output_file(const std::filesystem::path& file, const std::string& option);

class StagedOutput {
public:
    // Checks the folder (check_output_folder) now; `option` names it in errors ("--out").
    explicit StagedOutput(std::filesystem::path directory, std::string option = "--out");
    ~StagedOutput();
    StagedOutput(const StagedOutput&) = delete;
    StagedOutput& operator=(const StagedOutput&) = delete;

    // Encodes the image to its temporary file now (InputError naming the file if it cannot).
    void add_image(std::string name, const Image& image, ImageFormat format);
    void add_text(std::string name, std::string text);
    // A file outside the folder (a trace), written in the same commit; checked now.
    void add_text_at(const std::filesystem::path& file, std::string text, const std::string& option);
    // This run owns the folder: see above.
    void own_folder() { owns_ = true; }

    // Writes every staged file, or none: on any failure removes what it wrote, restores what it
    // replaced and throws InputError naming the file and the system's reason.
    // Returns the paths written, in the order staged.
    std::vector<std::filesystem::path> commit();

    const std::filesystem::path& directory() const { return directory_; }

private:
    struct Entry {
        std::filesystem::path target;
        std::string text;
        bool written = false;   // already in its temporary file (an image)
        bool in_folder = true;  // listed in the manifest
    };
    void claim(const std::filesystem::path& target) const;  // a file may be staged once
    void make_folder_for(const std::filesystem::path& target);
    void remove_temporaries();
    void write_manifest_and_clean();

    std::filesystem::path directory_;
    std::string option_;
    bool owns_ = false;
    bool committed_ = false;
    std::vector<Entry> entries_;
    std::vector<std::filesystem::path> made_folders_;  // by this run, deepest last
    std::vector<std::filesystem::path> temporaries_;   // images written ahead of the commit
};

}  // namespace pp5
