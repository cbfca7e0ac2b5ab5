#include "vtkHairStateReader.h"

#include "HairConversion.h"
#include "common/Machine.h"
#include "io/StateFile.h"
#include "simulation/GuideDrawing.h"

#include <vtkDoubleArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkTable.h>

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkHairStateReader);

struct vtkHairStateReader::Internals
{
  hair::StateFileReader Reader;
  /// The last drawing warning given and its file, so that each is given once per file.
  std::string Warned, WarnedFile;
};

vtkHairStateReader::vtkHairStateReader() : Internal(std::make_unique<Internals>())
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

vtkHairStateReader::~vtkHairStateReader() = default;

void vtkHairStateReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n"
     << indent << "PointsPerElement: " << this->PointsPerElement << "\n";
}

int vtkHairStateReader::CanReadFile(const char* fileName)
{
  hair::StateFileReader probe;
  return fileName && probe.open(fileName).ok() ? 1 : 0;
}

int vtkHairStateReader::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkPolyData" : "vtkTable");
  return 1;
}

int vtkHairStateReader::RequestInformation(vtkInformation*, vtkInformationVector**,
                                           vtkInformationVector* outputVector)
{
  // Opened anew each time: a file still being written has more frames every time.
  const hair::Status s = this->Internal->Reader.open(this->FileName);
  if (!s)
  {
    vtkErrorMacro(<< "Hair State Reader: " << s.message());
    return 0;
  }
  const std::vector<double>& times = this->Internal->Reader.times();
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  if (!times.empty())
  {
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(),
                 static_cast<int>(times.size()));
    const double range[2] = {times.front(), times.back()};
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  }
  // Under MPI each rank reads its piece of the strands (the energy table is piece 0's).
  for (int port = 0; port < 2; ++port)
  {
    outputVector->GetInformationObject(port)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  }
  return 1;
}

int vtkHairStateReader::RequestData(vtkInformation*, vtkInformationVector**,
                                    vtkInformationVector* outputVector)
{
  hair::StateFileReader& reader = this->Internal->Reader;
  vtkPolyData* strands = vtkPolyData::GetData(outputVector, 0);
  vtkTable* energy = vtkTable::GetData(outputVector, 1);
  const std::vector<double>& times = reader.times();
  if (times.empty())
  {
    vtkWarningMacro(<< "Hair State Reader: '" << this->FileName << "' holds no whole frame yet.");
    return 1;
  }
  // The frame at or before the requested time: the first one before the run starts, the
  // last one after it ends (as ParaView's readers of time series do); NaN is refused.
  std::int64_t frame = 0;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    if (std::isnan(t))
    {
      vtkErrorMacro(<< "Hair State Reader: '" << this->FileName
                    << "': the time asked for is NaN; ask for a time in [" << times.front() << ", "
                    << times.back() << "] s.");
      return 0;
    }
    const auto it = std::upper_bound(times.begin(), times.end(), t + 1e-12 * (1 + std::abs(t)));
    frame = std::max<std::int64_t>(0, (it - times.begin()) - 1);
  }
  // The piece asked for (ParaView's piece requests: under MPI, piece = rank of ranks).
  int piece = 0, pieces = 1;
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()))
  {
    pieces = std::max(1, outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()));
    piece = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
  }
  hair::StateFrame state;
  hair::StateHeader header;
  hair::Status read = hair::Status::Ok();
  if (pieces == 1)
  {
    header = reader.header();
    read = reader.readFrame(frame, state);
  }
  else
  {
    const std::vector<std::int64_t> mine = reader.pieceStrands(piece, pieces);
    header = reader.header().piece(mine);
    read = reader.readPiece(frame, mine, state);
  }
  if (!read)
  {
    vtkErrorMacro(<< "Hair State Reader: " << read.message());
    return 0;
  }
  // Drawn on every processor this process may use, or one per piece under MPI (the ranks
  // share the machine); each strand alone, so the same points on any number.
  hair::GuideDrawing drawing;
  const int threads = pieces > 1 ? 1 : hair::availableProcessors();
  if (hair::Status s = hair::drawGuides(header, state, this->PointsPerElement, threads, drawing);
      !s)
  {
    vtkErrorMacro(<< "Hair State Reader: '" << this->FileName << "': " << s.message());
    return 0;
  }
  if (!drawing.warning.empty() &&
      (drawing.warning != this->Internal->Warned || this->FileName != this->Internal->WarnedFile))
  {
    vtkWarningMacro(<< "Hair State Reader: '" << this->FileName << "': " << drawing.warning);
  }
  this->Internal->Warned = drawing.warning;
  this->Internal->WarnedFile = this->FileName;
  hair::convert::toStrands(drawing, strands);
  energy->Initialize();
  if (piece == 0)
  {
    std::vector<std::string> terms; // every column of a file's table is an energy term
    for (const auto& term : reader.energies())
    {
      terms.push_back(term.first);
    }
    hair::convert::toEnergyTable(times, reader.energies(), terms, energy);
  }
  strands->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), state.time);
  return 1;
}
