// The endpoints of `fixpoint serve`'s API (docs/serve-api.md): serve.cpp routes each request
// to one of them, inside guarded() (the token, the body's limits and the error answers).
#pragma once

#include "context.hpp"

#include <httplib.h>

#include <string>

namespace fp::host::serve_detail {

/// {"error": message}: the body of every refused request.
Json error_body(const std::string& message);

void api_state(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_plugins(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_check(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_params(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_edit(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_preview(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_frame(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_save(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_render(const Context& c, const httplib::Request& req, httplib::Response& res);
void api_recipe(const Context& c, const httplib::Request& req, httplib::Response& res);

} // namespace fp::host::serve_detail
