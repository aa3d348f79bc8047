//! controller.fmu's shared library: the FMI 3.0 functions rust-fmi
//! generates for [`mre_fmu::Controller`]. Everything else lives in `mre-fmu`.
fmi_export::export_fmu!(mre_fmu::Controller);
