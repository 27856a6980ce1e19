// SPDX-License-Identifier: Apache-2.0
// SHA-256 through OpenSSL's EVP digest interface (libcrypto), which picks the CPU's SHA
// instructions at run time.

#include "common/sha256.h"

#include <openssl/evp.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace wallcal {

struct Sha256::Context {
  EVP_MD_CTX* md = nullptr;
};

Sha256::Sha256() : context_(std::make_unique<Context>()) {
  context_->md = EVP_MD_CTX_new();
  if (context_->md == nullptr || EVP_DigestInit_ex(context_->md, EVP_sha256(), nullptr) != 1) {
    EVP_MD_CTX_free(context_->md);
    throw std::runtime_error("SHA-256: OpenSSL could not start a digest");
  }
}

Sha256::~Sha256() { EVP_MD_CTX_free(context_->md); }

void Sha256::Update(const void* data, size_t size) {
  if (size == 0) return;
  if (EVP_DigestUpdate(context_->md, data, size) != 1) {
    throw std::runtime_error("SHA-256: OpenSSL digest update failed");
  }
}

std::string Sha256::Hex() {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_DigestFinal_ex(context_->md, digest, &length) != 1 || length != 32) {
    throw std::runtime_error("SHA-256: OpenSSL digest final failed");
  }
  std::string hex;
  char digits[3];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(digits, sizeof(digits), "%02x", digest[i]);
    hex += digits;
  }
  return hex;
}

std::string Sha256Hex(const std::string& bytes) {
  Sha256 hash;
  hash.Update(bytes.data(), bytes.size());
  return hash.Hex();
}

std::string Sha256OfFile(const std::string& path) { return Sha256OfFile(path, nullptr); }

std::string Sha256OfFile(const std::string& path, const std::atomic<bool>* cancel) {
  // Only a regular file: a FIFO would block the open, a device never end (the digests are
  // computed on their own thread while the run checks its inputs, which refuses such files).
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::string();
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::string();
  Sha256 hash;
  std::vector<char> block(1 << 20);
  while (in) {
    if (cancel != nullptr && cancel->load()) return std::string();
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const std::streamsize got = in.gcount();
    if (got > 0) hash.Update(block.data(), static_cast<size_t>(got));
  }
  if (in.bad()) return std::string();
  return hash.Hex();
}

}  // namespace wallcal
