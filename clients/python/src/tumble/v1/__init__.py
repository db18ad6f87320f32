"""The protocol's messages, generated from proto/tumble/v1 by protoc (generate.sh)."""
