# Run by lcmtypes/CMakeLists.txt on every header lcm-gen wrote (cmake -P, HEADERS=a;b;...).
# Two holes in lcm-gen's decoders, found by tests/fuzz/lcm_messages_fuzzer:
# - an array is resized to the count just read before the bytes are checked, so a garbage
#   count (2^31 - 1) allocates gigabytes. Each element takes at least one byte, so a count
#   above the bytes left is refused first, as a decode failure;
# - a string length of 0 or less (it counts the NUL) throws std::length_error. Refused too.
foreach(header ${HEADERS})
  file(READ ${header} text)
  string(REGEX REPLACE
    "\n( *)this->([A-Za-z0-9_]+)\\.resize\\(this->([A-Za-z0-9_]+)\\);"
    "\n\\1if (this->\\3 < 0 || this->\\3 > maxlen - pos) return -1;  // aslam: guard_array_counts.cmake\n\\1this->\\2.resize(this->\\3);"
    guarded "${text}")
  string(REGEX REPLACE
    "if\\(__([A-Za-z0-9_]+)_len__ > maxlen - pos\\) return -1;"
    "if(__\\1_len__ < 1 || __\\1_len__ > maxlen - pos) return -1;  // aslam: guard_array_counts.cmake"
    guarded "${guarded}")
  file(WRITE ${header} "${guarded}")
endforeach()
