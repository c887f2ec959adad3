// The preview page (docs/serve-api.md): being written.
