"""The built-in application features, one module each, registered like third-party features."""
