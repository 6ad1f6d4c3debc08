#include "host/player/playlist.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <numeric>
#include <system_error>

namespace hmp::player {

namespace {

namespace fs = std::filesystem;

bool midi_name(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".mid" || ext == ".midi";
}

}  // namespace

std::vector<std::string> expand_songs(const std::vector<std::string>& arguments, std::vector<std::string>& notes) {
  std::vector<std::string> songs;
  for (const std::string& argument : arguments) {
    std::error_code ec;
    if (!fs::is_directory(argument, ec)) {
      songs.push_back(argument);
      continue;
    }
    std::vector<std::string> found;
    const auto options = fs::directory_options::skip_permission_denied;
    for (auto it = fs::recursive_directory_iterator(argument, options, ec); !ec && it != fs::end(it);
         it.increment(ec)) {
      std::error_code file_ec;
      if (it->is_regular_file(file_ec) && midi_name(it->path())) found.push_back(it->path().string());
    }
    if (ec) notes.push_back(argument + ": cannot list the folder (" + ec.message() + ")");
    if (found.empty() && !ec) notes.push_back(argument + ": no .mid or .midi files in the folder");
    std::sort(found.begin(), found.end());
    songs.insert(songs.end(), found.begin(), found.end());
  }
  return songs;
}

Playlist::Playlist(std::vector<std::string> songs, bool loop, bool shuffle, std::uint32_t seed)
    : songs_(std::move(songs)), loop_(loop), shuffle_(shuffle), random_(seed) {
  draw_order();
}

void Playlist::draw_order() {
  order_.resize(songs_.size());
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  if (shuffle_) std::shuffle(order_.begin(), order_.end(), random_);
}

bool Playlist::next() {
  if (at_ + 1 < order_.size()) {
    ++at_;
    return true;
  }
  if (!loop_) return false;
  ++pass_;
  at_ = 0;
  draw_order();
  return true;
}

void Playlist::previous() {
  if (at_ > 0) --at_;
}

}  // namespace hmp::player
