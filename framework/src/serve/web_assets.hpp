// The page's files (web/index.html, web/app.js, web/style.css), built into the binary by
// cmake/embed_web.cmake, so that `fixpoint serve` needs nothing installed beside it.
#pragma once

#include <span>
#include <string_view>

namespace fp::host::serve_detail {

struct WebAsset {
    std::string_view path;         ///< "/app.js"
    std::string_view content_type; ///< "text/javascript; charset=utf-8"
    std::string_view bytes;
};

std::span<const WebAsset> web_assets();

} // namespace fp::host::serve_detail
