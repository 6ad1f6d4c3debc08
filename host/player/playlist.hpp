#pragma once
// The songs `hmp play` was given (design §3): files and folders expanded into one list, and the order
// they play in (as given, or shuffled; once, or looping), moved by the n and p keys.
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace hmp::player {

// Each argument in order: a file as it is (whether it exists is found out when it is read), a folder
// as its .mid and .midi files (any letter case), its subfolders' included, sorted by their path. A folder
// without any adds a line to `notes` and nothing to the list.
std::vector<std::string> expand_songs(const std::vector<std::string>& arguments, std::vector<std::string>& notes);

class Playlist {
 public:
  // `songs` must not be empty. Shuffled: a new order on every pass, drawn from `seed`.
  Playlist(std::vector<std::string> songs, bool loop, bool shuffle, std::uint32_t seed);

  std::size_t size() const { return songs_.size(); }
  const std::string& current() const { return songs_[order_[at_]]; }
  std::size_t current_index() const { return order_[at_]; }  // in the list as given
  std::size_t position() const { return at_; }               // in this pass's order, from 0
  std::size_t pass() const { return pass_; }                 // 0 on the first pass

  // The next song; false at the end of the list when not looping (the position stays).
  bool next();
  // The song before; the first song of the first pass stays where it is (played again from its start).
  void previous();

 private:
  void draw_order();
  std::vector<std::string> songs_;
  std::vector<std::size_t> order_;
  std::size_t at_ = 0, pass_ = 0;
  bool loop_, shuffle_;
  std::mt19937 random_;
};

}  // namespace hmp::player
