//! Where cook spans go: a Chrome trace file (`--trace`) and, with the `otlp`
//! build feature, an OpenTelemetry collector over OTLP/HTTP (`--otlp`, e.g. Jaeger).

use std::path::Path;

use anyhow::Result;
use tracing_subscriber::prelude::*;

/// Flushes and closes every sink when dropped (at the end of the command).
#[derive(Default)]
pub struct Guard {
    _chrome: Option<tracing_chrome::FlushGuard>,
    #[cfg(feature = "otlp")]
    otlp: Option<opentelemetry_sdk::trace::SdkTracerProvider>,
}

impl Drop for Guard {
    fn drop(&mut self) {
        #[cfg(feature = "otlp")]
        if let Some(p) = self.otlp.take() {
            let _ = p.shutdown();
        }
    }
}

/// Installs the requested sinks; with none, tracing stays off (no overhead).
pub fn init(trace: Option<&Path>, otlp: Option<&str>) -> Result<Guard> {
    let mut guard = Guard::default();
    let chrome = trace.map(|path| {
        let (layer, flush) = tracing_chrome::ChromeLayerBuilder::new()
            .file(path)
            .include_args(true)
            .build();
        guard._chrome = Some(flush);
        layer
    });
    #[cfg(feature = "otlp")]
    let otel = match otlp {
        Some(endpoint) => {
            use opentelemetry::trace::TracerProvider as _;
            use opentelemetry_otlp::WithExportConfig as _;
            let exporter = opentelemetry_otlp::SpanExporter::builder()
                .with_http()
                .with_endpoint(endpoint)
                .build()?;
            let provider = opentelemetry_sdk::trace::SdkTracerProvider::builder()
                .with_simple_exporter(exporter)
                .with_resource(
                    opentelemetry_sdk::Resource::builder()
                        .with_service_name("geode")
                        .build(),
                )
                .build();
            let layer = tracing_opentelemetry::layer().with_tracer(provider.tracer("geode"));
            guard.otlp = Some(provider);
            Some(layer)
        }
        None => None,
    };
    #[cfg(not(feature = "otlp"))]
    if otlp.is_some() {
        anyhow::bail!("--otlp needs a geode built with the `otlp` feature (cargo build -p geode-cli --features otlp)");
    }
    #[cfg(not(feature = "otlp"))]
    let otel: Option<tracing_subscriber::layer::Identity> = None;
    if chrome.is_some() || otel.is_some() {
        tracing_subscriber::registry()
            .with(chrome)
            .with(otel)
            .init();
    }
    Ok(guard)
}
